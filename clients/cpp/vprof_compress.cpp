// vprof_compress: path compression against a running `vprof serve` — the same requests as
// clients/python/compress_example.py: the TUM recording freiburg1_xyz (3,000 samples) compressed
// to 90 waypoints and to a 5 mm tolerance, a recording whose times go back and a request for one
// waypoint. Checks, on its own: the 90-point path has 90 waypoints, strictly increasing times from
// the first sample's to the last's and the first and last sample's positions; each path's position
// RMSE and largest error, recomputed from the recording and the path interpolated linearly in time
// at every sample time, agree with the daemon's metrics to 1e-9 m; the tolerance path's largest
// error is within 5 mm with fewer than a tenth of the samples; the bad requests are
// INVALID_ARGUMENT naming recording.time and points. Exit 1 on any failure.
//
//   vprof_compress --recording FILE [--host H] [--port P] [--out RESPONSES.bin]
//
// --out writes every response (compute_time cleared) as length-delimited frames;
// clients/run-interop.sh compares the file with the Python example's byte for byte.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "vprof_wire.h"

using namespace vprof::v1;

namespace {

const double kTolerance = 0.005;  // m

// A TUM trajectory: `time tx ty tz qx qy qz qw` a line, `#` comments.
Poses read_tum(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot read " + path);
  Poses p;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    double v[8];
    for (double& x : v)
      if (!(s >> x)) throw std::runtime_error("not 8 numbers: " + line);
    p.add_time(v[0]); p.add_x(v[1]); p.add_y(v[2]); p.add_z(v[3]);
    p.add_qx(v[4]); p.add_qy(v[5]); p.add_qz(v[6]); p.add_qw(v[7]);
  }
  return p;
}

Poses line3(const std::vector<double>& times) {
  Poses p;
  for (size_t i = 0; i < times.size(); ++i) {
    p.add_time(times[i]); p.add_x(0.1 * i); p.add_y(0); p.add_z(0);
    p.add_qw(1); p.add_qx(0); p.add_qy(0); p.add_qz(0);
  }
  return p;
}

// The time-synchronous position error at every sample (the path interpolated linearly in time).
std::vector<double> position_errors(const Poses& rec, const Poses& path) {
  std::vector<double> errs;
  const auto& pt = path.time();
  for (int i = 0; i < rec.time_size(); ++i) {
    double t = rec.time(i);
    int j = int(std::upper_bound(pt.begin(), pt.end(), t) - pt.begin()) - 1;
    j = std::min(std::max(j, 0), path.time_size() - 2);
    double u = (t - pt[j]) / (pt[j + 1] - pt[j]);
    double dx = (1 - u) * path.x(j) + u * path.x(j + 1) - rec.x(i);
    double dy = (1 - u) * path.y(j) + u * path.y(j + 1) - rec.y(i);
    double dz = (1 - u) * path.z(j) + u * path.z(j + 1) - rec.z(i);
    errs.push_back(std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  return errs;
}

CompressedPath compress(vprofwire::Connection& conn, const CompressRequest& c) {
  Request req;
  req.set_request_id(c.request_id());
  *req.mutable_compress() = c;
  Response r = conn.call(req);
  if (r.body_case() != Response::kCompressed) throw std::runtime_error("expected a compressed response");
  return r.compressed();
}

bool check_path(const char* label, const CompressRequest& req, const CompressedPath& r) {
  const Poses& p = r.path();
  const Poses& rec = req.recording();
  if (r.has_error() || p.time_size() < 2) {
    std::printf("%-14s FAIL %s\n", label, r.error().message().c_str());
    return false;
  }
  std::vector<double> errs = position_errors(rec, p);
  double sse = 0, worst = 0;
  for (double e : errs) { sse += e * e; worst = std::max(worst, e); }
  double rmse = std::sqrt(sse / errs.size());
  bool ok = p.time(0) == rec.time(0) && p.time(p.time_size() - 1) == rec.time(rec.time_size() - 1) &&
            std::fabs(rmse - r.metrics().position_rmse()) <= 1e-9 &&
            std::fabs(worst - r.metrics().position_max()) <= 1e-9;
  for (int k = 1; k < p.time_size(); ++k) ok = ok && p.time(k - 1) < p.time(k);
  if (req.points() == 90) {
    int a = p.time_size() - 1, b = rec.time_size() - 1;
    ok = ok && p.time_size() == 90 && p.x(0) == rec.x(0) && p.y(0) == rec.y(0) && p.z(0) == rec.z(0) &&
         p.x(a) == rec.x(b) && p.y(a) == rec.y(b) && p.z(a) == rec.z(b);
  } else {
    ok = ok && worst <= kTolerance + 1e-12 && 10 * p.time_size() < rec.time_size();
  }
  std::printf("%-14s %s %d samples -> %d points, position RMSE %.4f mm (recomputed %.4f), max %.4f mm\n", label,
              ok ? "ok  " : "FAIL", rec.time_size(), p.time_size(), 1e3 * r.metrics().position_rmse(), 1e3 * rmse,
              1e3 * worst);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  std::string host = "127.0.0.1", out_path, recording;
  int port = 7450;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--host" && i + 1 < argc) host = argv[++i];
    else if (a == "--port" && i + 1 < argc) port = std::atoi(argv[++i]);
    else if (a == "--out" && i + 1 < argc) out_path = argv[++i];
    else if (a == "--recording" && i + 1 < argc) recording = argv[++i];
    else { std::fprintf(stderr, "usage: vprof_compress --recording FILE [--host H] [--port P] [--out FILE]\n"); return 2; }
  }
  if (recording.empty()) { std::fprintf(stderr, "vprof_compress: --recording FILE (a TUM trajectory) is needed\n"); return 2; }
  int failures = 0;
  std::vector<std::string> frames;
  try {
    vprofwire::Connection conn(host, port);
    Poses rec = read_tum(recording);
    std::vector<CompressRequest> reqs(4);
    reqs[0].set_request_id(401); *reqs[0].mutable_recording() = rec; reqs[0].set_points(90);
    reqs[1].set_request_id(402); *reqs[1].mutable_recording() = rec; reqs[1].set_tolerance(kTolerance);
    reqs[2].set_request_id(403); *reqs[2].mutable_recording() = line3({0, 1, 0.5});
    reqs[3].set_request_id(404); *reqs[3].mutable_recording() = line3({0, 1, 2}); reqs[3].set_points(1);
    const char* labels[] = {"compress 90", "compress 5mm", "compress back", "compress one"};
    const char* fields[] = {"", "", "recording.time", "points"};
    for (int k = 0; k < 4; ++k) {
      CompressedPath r = compress(conn, reqs[k]);
      bool ok;
      if (k < 2) {
        ok = check_path(labels[k], reqs[k], r);
      } else {
        ok = r.has_error() && r.error().code() == ERROR_CODE_INVALID_ARGUMENT && r.error().field() == fields[k];
        std::printf("%-14s %s %s (field %s)\n", labels[k], ok ? "ok  " : "FAIL",
                    ErrorCode_Name(r.error().code()).c_str(), r.error().field().c_str());
      }
      failures += ok ? 0 : 1;
      r.set_compute_time(0);
      frames.push_back(r.SerializeAsString());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vprof_compress: %s\n", e.what());
    return 1;
  }
  if (!out_path.empty()) vprofwire::write_frames(out_path, frames);
  return failures ? 1 : 0;
}
