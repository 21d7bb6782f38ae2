// vprof_kinematics: FK and IK against a running `vprof serve` — a library robot (UR5, closed
// form), the Franka Panda (numerical) and an inline URDF robot; the same requests as
// clients/python/kinematics_example.py. Every IK solution is sent back through FK and must
// reproduce the target to 1e-6 m and 1e-6 rad; an invalid target must come back as
// INVALID_ARGUMENT naming `target`. One line per request; exit 1 on any failure.
//
//   vprof_kinematics [--host H] [--port P] [--out RESPONSES.bin]
//
// --out writes every response (compute_time cleared, which varies) as length-delimited
// frames; clients/run-interop.sh compares the file with the Python example's byte for byte.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <google/protobuf/io/zero_copy_stream_impl.h>
#include <google/protobuf/util/delimited_message_util.h>

#include "vprof_wire.h"

using namespace vprof::v1;

namespace {

const char* kUrdf =
    "<robot name=\"two-axis\">\n"
    "  <link name=\"base\"/><link name=\"upper\"/><link name=\"tool\"/>\n"
    "  <joint name=\"turn\" type=\"revolute\"><parent link=\"base\"/><child link=\"upper\"/>\n"
    "    <origin xyz=\"0 0 0.3\"/><axis xyz=\"0 0 1\"/><limit lower=\"-3\" upper=\"3\" velocity=\"2\"/></joint>\n"
    "  <joint name=\"lift\" type=\"prismatic\"><parent link=\"upper\"/><child link=\"tool\"/>\n"
    "    <origin xyz=\"0.4 0 0\"/><axis xyz=\"0 0 1\"/><limit lower=\"0\" upper=\"0.5\" velocity=\"0.5\"/></joint>\n"
    "</robot>";

Pose pose(double x, double y, double z, double qw, double qx, double qy, double qz) {
  Pose p;
  p.set_x(x); p.set_y(y); p.set_z(z); p.set_qw(qw); p.set_qx(qx); p.set_qy(qy); p.set_qz(qz);
  return p;
}

struct Item {
  std::string label;
  bool is_fk;
  FkRequest fk;
  IkRequest ik;
};

std::vector<Item> requests() {
  std::vector<Item> out;
  Robot ur5; ur5.set_name("ur5");
  Item a{"fk ur5", true, {}, {}};
  a.fk.set_request_id(101); *a.fk.mutable_robot() = ur5;
  for (double q : {0.3, -1.2, 1.1, -0.5, 1.2, 0.4}) a.fk.add_joints(q);
  a.fk.set_link_frames(true);
  out.push_back(a);
  Item b{"ik ur5 all", false, {}, {}};
  b.ik.set_request_id(102); *b.ik.mutable_robot() = ur5;
  *b.ik.mutable_target() = pose(0.4, -0.1, 0.3, 0.0, 1.0, 0.0, 0.0);
  b.ik.set_all_solutions(true);
  out.push_back(b);
  Item c{"ik panda", false, {}, {}};
  c.ik.set_request_id(103); c.ik.mutable_robot()->set_name("franka-panda");
  *c.ik.mutable_target() = pose(0.5, 0.1, 0.4, 0.0, 1.0, 0.0, 0.0);
  for (double q : {0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8}) c.ik.add_seed(q);
  out.push_back(c);
  Robot inline_robot; inline_robot.set_urdf(kUrdf); inline_robot.set_tip_link("tool");
  Item d{"fk urdf", true, {}, {}};
  d.fk.set_request_id(104); *d.fk.mutable_robot() = inline_robot;
  d.fk.add_joints(0.5); d.fk.add_joints(0.2);
  out.push_back(d);
  Item e{"ik urdf", false, {}, {}};
  e.ik.set_request_id(105); *e.ik.mutable_robot() = inline_robot;
  *e.ik.mutable_target() = pose(0.4 * std::cos(0.5), 0.4 * std::sin(0.5), 0.5, std::cos(0.25), 0, 0, std::sin(0.25));
  out.push_back(e);
  Item f{"ik bad", false, {}, {}};
  f.ik.set_request_id(106); *f.ik.mutable_robot() = ur5;
  *f.ik.mutable_target() = pose(0.4, 0, 0, 0.5, 0, 0, 0);
  out.push_back(f);
  return out;
}

std::pair<double, double> pose_error(const Pose& a, const Pose& b) {
  double dp = std::sqrt(std::pow(a.x() - b.x(), 2) + std::pow(a.y() - b.y(), 2) + std::pow(a.z() - b.z(), 2));
  double dot = std::fabs(a.qw() * b.qw() + a.qx() * b.qx() + a.qy() * b.qy() + a.qz() * b.qz());
  return {dp, 2 * std::acos(std::min(1.0, dot))};
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
    else { std::fprintf(stderr, "usage: vprof_kinematics [--host H] [--port P] [--out FILE]\n"); return 2; }
  }
  int failures = 0;
  std::vector<std::string> frames;
  try {
    vprofwire::Connection conn(host, port);
    for (const Item& it : requests()) {
      Request req;
      bool ok = false;
      if (it.is_fk) {
        req.set_request_id(it.fk.request_id());
        *req.mutable_fk() = it.fk;
        Response resp = conn.call(req);
        if (resp.body_case() != Response::kFk) throw std::runtime_error("expected an fk response");
        FkResponse r = resp.fk();
        const Pose& t = r.tool();
        double n = std::sqrt(t.qw() * t.qw() + t.qx() * t.qx() + t.qy() * t.qy() + t.qz() * t.qz());
        ok = !r.has_error() && std::fabs(n - 1) < 1e-12 && r.jacobian_size() == 6 * (int)r.dof();
        std::printf("%-12s %s tool=(%.6f %.6f %.6f) manipulability=%.6g frames=%d\n", it.label.c_str(),
                    ok ? "ok  " : "FAIL", t.x(), t.y(), t.z(), r.manipulability(), r.link_frames_size());
        r.set_compute_time(0);
        frames.push_back(r.SerializeAsString());
      } else {
        req.set_request_id(it.ik.request_id());
        *req.mutable_ik() = it.ik;
        Response resp = conn.call(req);
        if (resp.body_case() != Response::kIk) throw std::runtime_error("expected an ik response");
        IkResponse r = resp.ik();
        if (it.label == "ik bad") {
          ok = r.has_error() && r.error().field() == "target" && r.error().code() == ERROR_CODE_INVALID_ARGUMENT;
          std::printf("%-12s %s %s (field %s)\n", it.label.c_str(), ok ? "ok  " : "FAIL",
                      ErrorCode_Name(r.error().code()).c_str(), r.error().field().c_str());
        } else {
          double wp = 0, wr = 0;
          for (const IkSolution& s : r.solutions()) {
            Request back;
            *back.mutable_fk()->mutable_robot() = it.ik.robot();
            *back.mutable_fk()->mutable_joints() = s.joints();
            back.set_request_id(1);
            Response br = conn.call(back);
            auto e = pose_error(br.fk().tool(), it.ik.target());
            wp = std::max(wp, e.first);
            wr = std::max(wr, e.second);
          }
          ok = !r.has_error() && r.solutions_size() > 0 && wp <= 1e-6 && wr <= 1e-6;
          std::printf("%-12s %s solver=%s solutions=%d worst FK residual %.1e m %.1e rad\n", it.label.c_str(),
                      ok ? "ok  " : "FAIL", r.solver().c_str(), r.solutions_size(), wp, wr);
        }
        r.set_compute_time(0);
        frames.push_back(r.SerializeAsString());
      }
      failures += ok ? 0 : 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vprof_kinematics: %s\n", e.what());
    return 1;
  }
  if (!out_path.empty()) vprofwire::write_frames(out_path, frames);
  return failures ? 1 : 0;
}
