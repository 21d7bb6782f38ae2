// vprof_load: requests per second and latency percentiles of `vprof serve`.
//
//   vprof_load --port P [--host H] (--request FILE.pb | --ping) [--connections 1,8,64]
//              [--duration SECONDS] [--warmup SECONDS]
//
// For each connection count C, C threads each open one connection and send the request
// back to back (one in flight per connection) for --duration seconds after a --warmup.
// Prints per C: requests, requests/s, p50/p95/p99/max latency (ms), and how many answers
// were not a profile without error (or not a pong with --ping). Built by
// `make -C clients/cpp load` (build/vprof_load).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

#include "vprof_wire.h"

using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
  GOOGLE_PROTOBUF_VERIFY_VERSION;
  std::string host = "127.0.0.1", request_file;
  int port = 7450;
  bool ping = false;
  double duration = 5, warmup = 1;
  std::vector<int> conns = {1, 8, 64};
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() { return std::string(i + 1 < argc ? argv[++i] : ""); };
    if (a == "--host") host = next();
    else if (a == "--port") port = std::atoi(next().c_str());
    else if (a == "--request") request_file = next();
    else if (a == "--ping") ping = true;
    else if (a == "--duration") duration = std::atof(next().c_str());
    else if (a == "--warmup") warmup = std::atof(next().c_str());
    else if (a == "--connections") {
      conns.clear();
      std::stringstream ss(next());
      std::string tok;
      while (std::getline(ss, tok, ',')) conns.push_back(std::atoi(tok.c_str()));
    } else {
      std::fprintf(stderr, "usage: vprof_load --port P (--request FILE.pb | --ping) [--connections 1,8,64] [--duration S] [--warmup S]\n");
      return 2;
    }
  }
  vprof::v1::Request proto_req;
  if (ping) {
    proto_req.mutable_ping()->set_payload("load");
  } else {
    if (request_file.empty()) { std::fprintf(stderr, "need --request FILE.pb or --ping\n"); return 2; }
    if (!proto_req.mutable_profile()->ParseFromString(vprofwire::read_file(request_file))) {
      std::fprintf(stderr, "%s is not a ProfileRequest\n", request_file.c_str());
      return 2;
    }
  }
  std::printf("%-6s %9s %10s %9s %9s %9s %9s %7s\n", "conns", "requests", "req/s", "p50 ms", "p95 ms",
              "p99 ms", "max ms", "bad");
  int status = 0;
  for (int c : conns) {
    std::vector<std::vector<double>> lat(c);
    std::atomic<long> bad{0};
    std::atomic<bool> failed{false};
    const auto t_start = Clock::now();
    const auto t_measure = t_start + std::chrono::duration<double>(warmup);
    const auto t_end = t_measure + std::chrono::duration<double>(duration);
    std::vector<std::thread> threads;
    for (int k = 0; k < c; ++k) {
      threads.emplace_back([&, k]() {
        try {
          vprofwire::Connection conn(host, port);
          vprof::v1::Request req = proto_req;
          uint64_t id = uint64_t(k + 1) << 32;
          while (true) {
            auto t0 = Clock::now();
            if (t0 >= t_end) break;
            req.set_request_id(++id);
            if (req.has_profile()) req.mutable_profile()->set_request_id(id);
            auto resp = conn.call(req);
            auto t1 = Clock::now();
            bool ok = resp.request_id() == id &&
                      (ping ? resp.has_pong() : (resp.has_profile() && !resp.profile().has_error()));
            if (t0 >= t_measure) {
              lat[k].push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
              if (!ok) ++bad;
            }
          }
        } catch (const std::exception& e) {
          std::fprintf(stderr, "connection %d: %s\n", k, e.what());
          failed = true;
        }
      });
    }
    for (auto& t : threads) t.join();
    std::vector<double> all;
    for (auto& v : lat) all.insert(all.end(), v.begin(), v.end());
    std::sort(all.begin(), all.end());
    auto pct = [&](double p) {
      if (all.empty()) return 0.0;
      size_t i = std::min(all.size() - 1, size_t(p / 100.0 * all.size()));
      return all[i];
    };
    std::printf("%-6d %9zu %10.1f %9.2f %9.2f %9.2f %9.2f %7ld%s\n", c, all.size(), all.size() / duration,
                pct(50), pct(95), pct(99), all.empty() ? 0.0 : all.back(), bad.load(),
                failed ? "  (connection failures)" : "");
    std::fflush(stdout);
    if (failed || bad > 0 || all.empty()) status = 1;
  }
  return status;
}
