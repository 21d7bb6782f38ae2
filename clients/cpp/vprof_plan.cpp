// vprof_plan: path planning against a running `vprof serve` — the same requests as
// clients/python/plan_example.py: the closed square of examples/plan-square.csv for a UR5 (z10,
// v500), a move that leaves the UR5's reach, and a request with a negative speed and a single
// waypoint. Checks, on its own: the square's plan is OK, its arrays have one entry per sample (q
// and qd dof entries per sample, row-major), the samples are time_step apart and the duration is
// the last one's time; every joint value is within the UR5's published limits (+-360 deg) and
// every joint speed, by forward differences of q, within its published 180 deg/s
// (src/robots/ur5.yaml); the TCP of every 20th sample, asked of the daemon by FK, is within the
// 10 mm zone (+ 0.1 mm) of the waypoint polyline. The move out of reach stops with
// PLAN_STATUS_OUT_OF_REACH (INFEASIBLE) between 0.3 and 0.8 m along; the bad request is
// INVALID_ARGUMENT naming speed and waypoints. Exit 1 on any failure.
//
//   vprof_plan [--host H] [--port P] [--square examples/plan-square.csv] [--out RESPONSES.bin]
//
// --out writes every plan response (compute_time cleared) as length-delimited frames;
// clients/run-interop.sh compares the file with the Python example's byte for byte.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "vprof_wire.h"

using namespace vprof::v1;

namespace {

const double kLimit = 2 * M_PI;  // rad, the UR5's +-360 deg
const double kSpeed = M_PI;      // rad/s, the UR5's 180 deg/s
const double kZone = 0.01;       // m, z10

// time,x,y,z,qw,qx,qy,qz per line after the header
std::vector<std::array<double, 8>> read_square(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot read " + path);
  std::vector<std::array<double, 8>> rows;
  std::string line;
  std::getline(f, line);
  while (std::getline(f, line)) {
    if (line.find_first_not_of(" \r\n") == std::string::npos) continue;
    std::array<double, 8> r{};
    std::stringstream ss(line);
    std::string cell;
    for (int i = 0; i < 8 && std::getline(ss, cell, ','); ++i) r[i] = std::stod(cell);
    rows.push_back(r);
  }
  return rows;
}

Poses poses(const std::vector<std::array<double, 8>>& rows) {
  Poses p;
  for (const auto& r : rows) {
    p.add_time(r[0]); p.add_x(r[1]); p.add_y(r[2]); p.add_z(r[3]);
    p.add_qw(r[4]); p.add_qx(r[5]); p.add_qy(r[6]); p.add_qz(r[7]);
  }
  return p;
}

Robot named(const std::string& n) { Robot r; r.set_name(n); return r; }

PlanResponse plan(vprofwire::Connection& conn, const PlanRequest& p) {
  Request req;
  req.set_request_id(p.request_id());
  *req.mutable_plan() = p;
  Response r = conn.call(req);
  if (r.body_case() != Response::kPlan) throw std::runtime_error("expected a plan response");
  return r.plan();
}

Pose fk(vprofwire::Connection& conn, const std::string& robot, const std::vector<double>& q) {
  Request req;
  req.set_request_id(1);
  *req.mutable_fk()->mutable_robot() = named(robot);
  for (double x : q) req.mutable_fk()->add_joints(x);
  Response r = conn.call(req);
  if (r.body_case() != Response::kFk) throw std::runtime_error("expected an fk response");
  return r.fk().tool();
}

double segment_distance(const std::array<double, 3>& p, const std::array<double, 3>& a, const std::array<double, 3>& b) {
  double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  double l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  double u = 0;
  if (l2 > 0) u = std::max(0.0, std::min(1.0, ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1] + (p[2] - a[2]) * d[2]) / l2));
  double s = 0;
  for (int i = 0; i < 3; ++i) s += std::pow(a[i] + u * d[i] - p[i], 2);
  return std::sqrt(s);
}

bool check_square(vprofwire::Connection& conn, const std::vector<std::array<double, 8>>& rows, const PlanResponse& r) {
  const int n = (int)r.dof(), m = r.time_size();
  bool ok = r.status() == PLAN_STATUS_OK && !r.has_error() && n == 6 && m > 100;
  for (int len : {r.distance_size(), r.velocity_size(), r.acceleration_size(), r.jerk_size()}) ok = ok && len == m;
  ok = ok && r.q_size() == m * n && r.qd_size() == m * n;
  ok = ok && r.duration() > 0 && r.duration() == r.time(m - 1);
  for (int k = 0; ok && k + 1 < m; ++k) ok = std::fabs(r.time(k + 1) - r.time(k) - r.time_step()) < 1e-9;
  if (!ok) {
    std::printf("%-12s FAIL %s: %d samples of %d joints\n", "plan square", PlanStatus_Name(r.status()).c_str(), m, n);
    return false;
  }
  double worst_q = 0, worst_v = 0;
  for (double x : r.q()) worst_q = std::max(worst_q, std::fabs(x));
  for (int k = 0; k + 1 < m; ++k)
    for (int i = 0; i < n; ++i) worst_v = std::max(worst_v, std::fabs(r.q((k + 1) * n + i) - r.q(k * n + i)) / r.time_step());
  ok = worst_q <= kLimit && worst_v <= kSpeed * 1.001;
  std::vector<int> ks;
  for (int k = 0; k < m; k += 20) ks.push_back(k);
  ks.push_back(m - 1);
  double worst_tcp = 0;
  for (int k : ks) {
    std::vector<double> q(r.q().begin() + k * n, r.q().begin() + (k + 1) * n);
    Pose t = fk(conn, "ur5", q);
    double d = 1e300;
    for (size_t j = 0; j + 1 < rows.size(); ++j)
      d = std::min(d, segment_distance({t.x(), t.y(), t.z()}, {rows[j][1], rows[j][2], rows[j][3]},
                                       {rows[j + 1][1], rows[j + 1][2], rows[j + 1][3]}));
    worst_tcp = std::max(worst_tcp, d);
  }
  ok = ok && worst_tcp <= kZone + 1e-4;
  double peak = 0;
  for (double v : r.velocity()) peak = std::max(peak, v);
  std::printf("%-12s %s %s: %d samples, dt %.3f s, duration %.3f s, route %.1f mm, %d zones, peak %.1f mm/s, "
              "largest |q| %.3f rad, joint speed %.3f rad/s, TCP off the polyline %.2f mm\n",
              "plan square", ok ? "ok  " : "FAIL", PlanStatus_Name(r.status()).c_str(), m, r.time_step(), r.duration(),
              1000 * r.route_length(), r.zones_size(), 1000 * peak, worst_q, worst_v, 1000 * worst_tcp);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  std::string host = "127.0.0.1", out_path, square_path;
  int port = 7450;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--host" && i + 1 < argc) host = argv[++i];
    else if (a == "--port" && i + 1 < argc) port = std::atoi(argv[++i]);
    else if (a == "--square" && i + 1 < argc) square_path = argv[++i];
    else if (a == "--out" && i + 1 < argc) out_path = argv[++i];
    else { std::fprintf(stderr, "usage: vprof_plan [--host H] [--port P] [--square FILE.csv] [--out FILE]\n"); return 2; }
  }
  if (square_path.empty()) {
    // examples/plan-square.csv beside the clients: <repo>/clients/cpp/build/vprof_plan
    std::string self = argv[0];
    std::string dir = self.substr(0, self.find_last_of('/') + 1);
    square_path = dir + "../../../examples/plan-square.csv";
  }
  int failures = 0;
  std::vector<std::string> frames;
  try {
    auto rows = read_square(square_path);
    vprofwire::Connection conn(host, port);

    PlanRequest square;
    square.set_request_id(301);
    *square.mutable_waypoints() = poses(rows);
    *square.mutable_robot() = named("ur5");
    square.set_speed(0.5);
    square.set_zone(kZone);

    PlanRequest far;
    far.set_request_id(302);
    *far.mutable_robot() = named("ur5");
    *far.mutable_waypoints() = poses({{0, 0.4, 0, 0.3, 0, 1, 0, 0}, {0, 1.2, 0, 0.3, 0, 1, 0, 0}});
    far.mutable_waypoints()->clear_time();

    PlanRequest bad;
    bad.set_request_id(303);
    *bad.mutable_robot() = named("ur5");
    bad.set_speed(-0.5);
    *bad.mutable_waypoints() = poses({{0, 0.4, 0, 0.3, 0, 1, 0, 0}});
    bad.mutable_waypoints()->clear_time();

    PlanResponse r1 = plan(conn, square);
    failures += check_square(conn, rows, r1) ? 0 : 1;
    r1.set_compute_time(0);
    frames.push_back(r1.SerializeAsString());

    PlanResponse r2 = plan(conn, far);
    bool ok2 = r2.status() == PLAN_STATUS_OUT_OF_REACH && r2.error().code() == ERROR_CODE_INFEASIBLE &&
               r2.stop_distance() > 0.3 && r2.stop_distance() < 0.8 &&
               std::fabs(r2.stop_pose().x() - (0.4 + r2.stop_distance())) < 1e-9 && r2.time_size() == 0;
    std::printf("%-12s %s %s at %.1f mm: %s\n", "plan far", ok2 ? "ok  " : "FAIL", PlanStatus_Name(r2.status()).c_str(),
                1000 * r2.stop_distance(), r2.error().message().c_str());
    failures += ok2 ? 0 : 1;
    r2.set_compute_time(0);
    frames.push_back(r2.SerializeAsString());

    PlanResponse r3 = plan(conn, bad);
    std::vector<std::string> fields;
    for (const Error& e : r3.errors()) fields.push_back(e.field());
    std::sort(fields.begin(), fields.end());
    bool ok3 = r3.status() == PLAN_STATUS_INVALID_ARGUMENT && r3.error().code() == ERROR_CODE_INVALID_ARGUMENT &&
               fields == std::vector<std::string>{"speed", "waypoints"} &&
               r3.error().message().find("-0.5 m/s") != std::string::npos && r3.time_size() == 0;
    std::printf("%-12s %s %s (fields %s, %s)\n", "plan bad", ok3 ? "ok  " : "FAIL", ErrorCode_Name(r3.error().code()).c_str(),
                fields.size() > 0 ? fields[0].c_str() : "", fields.size() > 1 ? fields[1].c_str() : "");
    failures += ok3 ? 0 : 1;
    r3.set_compute_time(0);
    frames.push_back(r3.SerializeAsString());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vprof_plan: %s\n", e.what());
    return 1;
  }
  if (!out_path.empty()) vprofwire::write_frames(out_path, frames);
  return failures ? 1 : 0;
}
