// vprof_select: robot selection against a running `vprof serve` — the same requests as
// clients/python/select_example.py: which of the UR5, the ABB IRB 140 and the Franka Panda reach
// four targets (three UR5 tool poses asked of the daemon by FK, one 3 m away) in a cell of a
// floor and a box given in millimetres, with a 4 kg payload and 1 cm clearance; and a request
// with a negative payload and no targets. Checks: the Panda (3 kg) is rejected by the payload
// filter, the far target fails with SELECT_FAILURE_REACH, every reported joint solution sent
// back through FK reproduces its target to 1e-6 m and 1e-6 rad with at least 1 cm clearance, the
// bad request is INVALID_ARGUMENT naming payload and targets. Exit 1 on any failure.
//
//   vprof_select [--host H] [--port P] [--out RESPONSES.bin]
//
// --out writes every select response (compute_time cleared) as length-delimited frames;
// clients/run-interop.sh compares the file with the Python example's byte for byte.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "vprof_wire.h"

using namespace vprof::v1;

namespace {

const std::vector<std::vector<double>> kJoints = {
    {0.3, -1.2, 1.1, -0.5, 1.2, 0.4}, {-0.2, -1.4, 1.5, -1.2, -1.3, 0.1}, {0.6, -1.0, 1.3, -1.8, -1.5, 0.0}};

std::vector<Mesh> cell() {
  Mesh floor;
  for (double v : {-2.0, -2.0, -0.15, 2.0, -2.0, -0.15, 2.0, 2.0, -0.15, -2.0, 2.0, -0.15}) floor.add_vertices(v);
  for (unsigned t : {0, 1, 2, 0, 2, 3}) floor.add_triangles(t);
  Mesh box;
  for (double x : {-150.0, 150.0})
    for (double y : {-150.0, 150.0})
      for (double z : {-100.0, 100.0}) { box.add_vertices(x); box.add_vertices(y); box.add_vertices(z); }
  for (unsigned t : {0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1, 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3})
    box.add_triangles(t);
  box.set_scale(0.001);
  Pose* p = box.mutable_pose();
  p->set_x(-0.5); p->set_y(-0.4); p->set_z(0.0); p->set_qw(std::cos(0.2)); p->set_qz(std::sin(0.2));
  return {floor, box};
}

Robot named(const std::string& n) { Robot r; r.set_name(n); return r; }

std::pair<double, double> pose_error(const Pose& a, const Pose& b) {
  double dp = std::sqrt(std::pow(a.x() - b.x(), 2) + std::pow(a.y() - b.y(), 2) + std::pow(a.z() - b.z(), 2));
  double dot = std::fabs(a.qw() * b.qw() + a.qx() * b.qx() + a.qy() * b.qy() + a.qz() * b.qz());
  return {dp, 2 * std::acos(std::min(1.0, dot))};
}

Pose fk(vprofwire::Connection& conn, const std::string& robot, const google::protobuf::RepeatedField<double>& q) {
  Request req;
  req.set_request_id(1);
  *req.mutable_fk()->mutable_robot() = named(robot);
  *req.mutable_fk()->mutable_joints() = q;
  Response r = conn.call(req);
  if (r.body_case() != Response::kFk) throw std::runtime_error("expected an fk response");
  return r.fk().tool();
}

SelectResponse select(vprofwire::Connection& conn, const SelectRequest& s) {
  Request req;
  req.set_request_id(s.request_id());
  *req.mutable_select() = s;
  Response r = conn.call(req);
  if (r.body_case() != Response::kSelect) throw std::runtime_error("expected a select response");
  return r.select();
}

bool check_cell(vprofwire::Connection& conn, const SelectRequest& req, const SelectResponse& r) {
  bool ok = !r.has_error() && r.robots_size() == 3;
  for (int i = 0; i < r.robots_size(); ++i) {
    const SelectRobotResult& robot = r.robots(i);
    ok = ok && robot.rank() == (unsigned)(i + 1);
    double wp = 0, wr = 0;
    for (int k = 0; k < robot.targets_size() && k < req.targets_size(); ++k) {
      const SelectTarget& t = robot.targets(k);
      if (t.joints_size() > 0) {
        auto e = pose_error(fk(conn, robot.robot(), t.joints()), req.targets(k));
        wp = std::max(wp, e.first);
        wr = std::max(wr, e.second);
        ok = ok && t.reached() && t.clearance() >= req.clearance() && !t.clearance_body().empty();
      } else {
        ok = ok && !t.reached() && !t.failure().empty() && t.failure_code() != SELECT_FAILURE_NONE;
      }
    }
    ok = ok && wp <= 1e-6 && wr <= 1e-6;
    if (!robot.rejected().empty()) {
      std::printf("  %d %-14s rejected: %s\n", i + 1, robot.robot().c_str(), robot.rejected().c_str());
      ok = ok && robot.robot() == "franka-panda" && robot.rejected().find("payload") != std::string::npos;
    } else {
      const SelectTarget& far = robot.targets(robot.targets_size() - 1);
      ok = ok && far.failure_code() == SELECT_FAILURE_REACH && robot.total() == 4;
      std::printf("  %d %-14s reached %u/%u  min clearance %.1f mm (%s)  min manipulability %.4f  score %.1f"
                  "  worst FK residual %.1e m %.1e rad  %s: %s\n",
                  i + 1, robot.robot().c_str(), robot.reached(), robot.total(), 1000 * robot.min_clearance(),
                  robot.min_clearance_body().c_str(), robot.min_manipulability(), robot.score(), wp, wr,
                  far.label().c_str(), SelectFailure_Name(far.failure_code()).c_str());
    }
  }
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  std::string host = "127.0.0.1", out_path;
  int port = 7450;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--host" && i + 1 < argc) host = argv[++i];
    else if (a == "--port" && i + 1 < argc) port = std::atoi(argv[++i]);
    else if (a == "--out" && i + 1 < argc) out_path = argv[++i];
    else { std::fprintf(stderr, "usage: vprof_select [--host H] [--port P] [--out FILE]\n"); return 2; }
  }
  int failures = 0;
  std::vector<std::string> frames;
  try {
    vprofwire::Connection conn(host, port);
    SelectRequest good;
    good.set_request_id(201);
    for (const Mesh& m : cell()) *good.add_environment() = m;
    good.mutable_tool_capsule()->set_az(-0.03);
    good.mutable_tool_capsule()->set_radius(0.01);
    good.set_payload(4.0);
    good.set_clearance(0.01);
    for (const auto& q : kJoints) {
      google::protobuf::RepeatedField<double> joints(q.begin(), q.end());
      *good.add_targets() = fk(conn, "ur5", joints);
    }
    Pose* far = good.add_targets();
    far->set_x(3.0); far->set_z(0.5); far->set_qx(1.0);
    for (const char* n : {"ur5", "ABB IRB 140", "franka-panda"}) *good.add_robots() = named(n);

    SelectRequest bad;
    bad.set_request_id(202);
    bad.set_payload(-1.0);
    bad.set_clearance(0.01);
    *bad.add_robots() = named("ur5");

    std::printf("%-12s\n", "select cell");
    SelectResponse r1 = select(conn, good);
    bool ok1 = check_cell(conn, good, r1);
    std::printf("%-12s %s\n", "", ok1 ? "ok" : "FAIL");
    failures += ok1 ? 0 : 1;
    r1.set_compute_time(0);
    frames.push_back(r1.SerializeAsString());

    SelectResponse r2 = select(conn, bad);
    std::vector<std::string> fields;
    for (const Error& e : r2.errors()) fields.push_back(e.field());
    std::sort(fields.begin(), fields.end());
    bool ok2 = r2.error().code() == ERROR_CODE_INVALID_ARGUMENT && fields == std::vector<std::string>{"payload", "targets"} &&
               r2.error().message().find("-1.0 kg") != std::string::npos && r2.robots_size() == 0;
    std::printf("%-12s %s %s (fields %s, %s)\n", "select bad", ok2 ? "ok  " : "FAIL",
                ErrorCode_Name(r2.error().code()).c_str(), fields.size() > 0 ? fields[0].c_str() : "",
                fields.size() > 1 ? fields[1].c_str() : "");
    failures += ok2 ? 0 : 1;
    r2.set_compute_time(0);
    frames.push_back(r2.SerializeAsString());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vprof_select: %s\n", e.what());
    return 1;
  }
  if (!out_path.empty()) vprofwire::write_frames(out_path, frames);
  return failures ? 1 : 0;
}
