// vprof_check: sends bare ProfileRequest files (examples/*.pb) to a running `vprof serve`
// and checks every profile it receives against the request's limits with its OWN checker
// (independent of vprof's), 1e-9 relative tolerance. One line per case; exit 1 on any
// failure.
//
//   vprof_check [--host H] [--port P] [--transport-only] FILE.pb...
//   vprof_check --selftest     (the checker against hand-made legal and illegal profiles)
//
// --transport-only checks only the exchange (a profile body echoing request_id): for the
// stub daemon, which has no generator.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "vprof_wire.h"

using vprof::v1::ProfileRequest;
using vprof::v1::ProfileResponse;

namespace {

const double kRel = 1e-9;

// <= with 1e-9 relative slack; `scale` keeps the slack meaningful near zero.
bool le(double x, double limit, double scale) {
  return x <= limit + kRel * std::max(std::fabs(limit), scale);
}
bool ge(double x, double limit, double scale) {
  return x >= limit - kRel * std::max(std::fabs(limit), scale);
}

std::string fmt(const char* f, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

// Every problem of the profile p for request q (empty when legal).
std::vector<std::string> check_profile(const ProfileRequest& q, const ProfileResponse& p) {
  std::vector<std::string> bad;
  auto fail = [&](const std::string& s) { if (bad.size() < 8) bad.push_back(s); };
  const auto& v = p.velocity();
  const size_t n1 = v.size();
  if (p.has_error()) fail("error " + vprof::v1::ErrorCode_Name(p.error().code()) + ": " + p.error().message());
  if (n1 < 2) { fail("fewer than 2 samples"); return bad; }
  if ((size_t)p.time_size() != n1 || (size_t)p.distance_size() != n1 ||
      (size_t)p.acceleration_size() != n1 || (size_t)p.jerk_size() != n1)
    fail("sample arrays of different lengths");
  const double dt = p.time_step() > 0 ? p.time_step() : (q.time_step() > 0 ? q.time_step() : 0.125);
  if (q.time_step() > 0 && p.time_step() != q.time_step()) fail(fmt("time_step %g != requested %g", p.time_step(), q.time_step()));

  double vmax_lim = 0;
  for (const auto& z : q.speed_limits()) vmax_lim = std::max(vmax_lim, z.velocity());
  const double vscale = std::max(vmax_lim, 1e-3);
  const double ascale = std::max(std::fabs(q.min_acceleration()), std::fabs(q.max_acceleration()));
  const double jscale = std::max(std::fabs(q.min_jerk()), std::fabs(q.max_jerk()));

  // distance: our own trapezoidal integral
  std::vector<double> s(n1, 0.0);
  for (size_t k = 0; k + 1 < n1; ++k) s[k + 1] = s[k] + 0.5 * (v[k] + v[k + 1]) * dt;
  for (size_t k = 0; k < n1 && k < (size_t)p.distance_size(); ++k)
    if (std::fabs(p.distance(k) - s[k]) > 1e-6 * std::max(1.0, std::fabs(s[k]))) {
      fail(fmt("distance[%g]=%.12g but the integral of velocity is %.12g", k, p.distance(k), s[k]));
      break;
    }

  // lowest speed limit on [a, b]; zone i holds on [start_i, start_{i+1})
  auto lowest_limit = [&](double a, double b) {
    double lim = INFINITY;
    const int nz = q.speed_limits_size();
    for (int i = 0; i < nz; ++i) {
      double lo = q.speed_limits(i).start_distance();
      double hi = i + 1 < nz ? q.speed_limits(i + 1).start_distance() : INFINITY;
      if (lo <= b && hi > a) lim = std::min(lim, q.speed_limits(i).velocity());
    }
    return lim;
  };

  for (size_t k = 0; k < n1; ++k)
    if (!ge(v[k], 0.0, vscale)) { fail(fmt("negative velocity v[%g]=%g", k, v[k])); break; }
  for (size_t k = 0; k + 1 < n1; ++k) {
    double lim = lowest_limit(s[k], s[k + 1]);
    double vm = std::max(v[k], v[k + 1]);
    if (!le(vm, lim, vscale)) { fail(fmt("speed %.9g above limit %.9g at step %g", vm, lim, k)); break; }
  }
  // accelerations from the velocities, then the end acceleration
  std::vector<double> a(n1);
  for (size_t k = 0; k + 1 < n1; ++k) a[k] = (v[k + 1] - v[k]) / dt;
  a[n1 - 1] = q.end_acceleration();
  for (size_t k = 0; k + 1 < n1; ++k)
    if (!ge(a[k], q.min_acceleration(), ascale) || !le(a[k], q.max_acceleration(), ascale)) {
      fail(fmt("acceleration a[%g]=%.9g outside [%g, max]", k, a[k], q.min_acceleration()));
      break;
    }
  // jerks, including into the first acceleration from start_acceleration
  std::vector<double> j;
  j.push_back((a[0] - q.start_acceleration()) / dt);
  for (size_t k = 0; k + 1 < n1; ++k) j.push_back((a[k + 1] - a[k]) / dt);
  for (size_t k = 0; k < j.size(); ++k)
    if (!ge(j[k], q.min_jerk(), jscale) || !le(j[k], q.max_jerk(), jscale)) {
      fail(fmt("jerk %.9g outside [%g, %g]", j[k], q.min_jerk(), q.max_jerk()) + " at index " +
           std::to_string(k) + " (0 = into a_0 from start_acceleration)");
      break;
    }
  if (std::fabs(v[0] - q.start_velocity()) > kRel * vscale) fail(fmt("v_0=%.12g != start_velocity %.12g", v[0], q.start_velocity()));
  if (std::fabs(v[n1 - 1] - q.end_velocity()) > kRel * vscale) fail(fmt("v_N=%.12g != end_velocity %.12g", v[n1 - 1], q.end_velocity()));
  const double tol = q.end_tolerance() > 0 ? q.end_tolerance() : 0.01;
  if (!(std::fabs(s[n1 - 1] - q.route_length()) <= tol * (1 + kRel)))
    fail(fmt("s_N=%.9g but route_length %.9g (tolerance %g)", s[n1 - 1], q.route_length(), tol));
  if (!p.legal()) fail("the daemon says legal=false");
  return bad;
}

// ------------------------------------------------------------------ self test
ProfileRequest cruise_request() {
  ProfileRequest q;
  q.set_route_length(10.0);
  auto* z = q.add_speed_limits();
  z->set_start_distance(0);
  z->set_velocity(2.0);
  q.set_min_acceleration(-1); q.set_max_acceleration(1);
  q.set_min_jerk(-2); q.set_max_jerk(2);
  q.set_start_velocity(1); q.set_end_velocity(1);
  q.set_time_step(0.125);
  return q;
}
// 1 m/s for 10 s: legal for cruise_request.
ProfileResponse cruise_profile() {
  ProfileResponse p;
  p.set_time_step(0.125);
  for (int k = 0; k <= 80; ++k) {
    p.add_time(k * 0.125); p.add_velocity(1.0); p.add_distance(k * 0.125);
    p.add_acceleration(0); p.add_jerk(0);
  }
  p.set_legal(true); p.set_converged(true);
  return p;
}
void redistance(ProfileResponse* p) {
  double s = 0;
  p->set_distance(0, 0);
  for (int k = 1; k < p->velocity_size(); ++k) {
    s += 0.5 * (p->velocity(k - 1) + p->velocity(k)) * p->time_step();
    p->set_distance(k, s);
  }
}
int selftest() {
  int failures = 0;
  auto expect = [&](const char* name, const ProfileRequest& q, const ProfileResponse& p, bool legal) {
    auto bad = check_profile(q, p);
    bool ok = bad.empty() == legal;
    std::printf("%s selftest %-34s %s%s\n", ok ? "PASS" : "FAIL", name, legal ? "legal" : "illegal",
                bad.empty() ? "" : (": " + bad[0]).c_str());
    failures += ok ? 0 : 1;
  };
  ProfileRequest q = cruise_request();
  expect("cruise", q, cruise_profile(), true);
  { auto p = cruise_profile(); p.set_velocity(40, 2.5); redistance(&p); expect("speed above limit", q, p, false); }
  { auto p = cruise_profile(); p.set_velocity(40, 1.0 + 0.125 * 1.01); redistance(&p); expect("acceleration above max", q, p, false); }
  { auto p = cruise_profile(); p.set_velocity(40, 1.0 + 0.125 * 0.9); redistance(&p); expect("jerk (one bump)", q, p, false); }
  { auto q2 = q; q2.set_start_acceleration(0.5); expect("jerk from start_acceleration", q2, cruise_profile(), false); }
  { auto q2 = q; q2.set_start_velocity(0.5); expect("start velocity", q2, cruise_profile(), false); }
  { auto q2 = q; q2.set_end_velocity(0.9); expect("end velocity", q2, cruise_profile(), false); }
  { auto q2 = q; q2.set_route_length(10.02); expect("route end 2 cm short", q2, cruise_profile(), false); }
  { auto q2 = q; q2.set_route_length(10.005); expect("route end within 1 cm", q2, cruise_profile(), true); }
  { auto q2 = q; auto* z = q2.add_speed_limits(); z->set_start_distance(5.0); z->set_velocity(0.99);
    expect("second zone below cruise", q2, cruise_profile(), false); }
  { auto q2 = q; auto* z = q2.add_speed_limits(); z->set_start_distance(5.0); z->set_velocity(1.0 * (1 + 5e-10));
    expect("limit within 1e-9 relative", q2, cruise_profile(), true); }
  { auto p = cruise_profile(); p.set_legal(false); expect("legal=false reported", q, p, false); }
  { auto p = cruise_profile(); p.set_distance(3, 99); expect("distance array inconsistent", q, p, false); }
  { auto q2 = q; q2.set_start_velocity(0); q2.set_end_velocity(0); q2.set_route_length(0);
    auto p = cruise_profile();
    for (int k = 0; k <= 80; ++k) p.set_velocity(k, 0);
    p.set_velocity(40, -1e-6); redistance(&p);
    expect("negative velocity", q2, p, false); }
  return failures ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  GOOGLE_PROTOBUF_VERIFY_VERSION;
  std::string host = "127.0.0.1";
  int port = 7450;
  bool transport_only = false;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--host" && i + 1 < argc) host = argv[++i];
    else if (a == "--port" && i + 1 < argc) port = std::atoi(argv[++i]);
    else if (a == "--transport-only") transport_only = true;
    else if (a == "--selftest") return selftest();
    else if (a == "-h" || a == "--help") {
      std::puts("usage: vprof_check [--host H] [--port P] [--transport-only] FILE.pb... | --selftest");
      return 0;
    } else files.push_back(a);
  }
  if (files.empty()) { std::fprintf(stderr, "no request files\n"); return 2; }
  int failures = 0;
  try {
    vprofwire::Connection conn(host, port);
    uint64_t id = 0;
    for (const auto& f : files) {
      ++id;
      std::string name = f.substr(f.find_last_of('/') + 1);
      ProfileRequest q;
      if (!q.ParseFromString(vprofwire::read_file(f))) {
        std::printf("FAIL %-24s not a ProfileRequest\n", name.c_str());
        ++failures;
        continue;
      }
      q.set_request_id(id);
      vprof::v1::Request req;
      req.set_request_id(id);
      *req.mutable_profile() = q;
      vprof::v1::Response resp = conn.call(req);
      std::vector<std::string> bad;
      if (resp.request_id() != id) bad.push_back("response request_id " + std::to_string(resp.request_id()));
      if (!resp.has_profile()) {
        bad.push_back(resp.has_error() ? "error " + vprof::v1::ErrorCode_Name(resp.error().code()) + ": " + resp.error().message()
                                       : "no profile body");
      } else {
        if (resp.profile().request_id() != id) bad.push_back("profile request_id " + std::to_string(resp.profile().request_id()));
        if (!transport_only) {
          auto more = check_profile(q, resp.profile());
          bad.insert(bad.end(), more.begin(), more.end());
        }
      }
      const auto& p = resp.profile();
      if (bad.empty()) {
        std::printf("PASS %-24s samples=%d duration=%.3fs peak=%.3fm/s iterations=%u compute=%.1fms%s\n",
                    name.c_str(), p.velocity_size(), p.duration(),
                    p.velocity_size() ? *std::max_element(p.velocity().begin(), p.velocity().end()) : 0.0,
                    p.iterations(), p.compute_time() * 1e3, transport_only ? " (transport only)" : "");
      } else {
        ++failures;
        std::printf("FAIL %-24s %s\n", name.c_str(), bad[0].c_str());
        for (size_t k = 1; k < bad.size(); ++k) std::printf("     %-24s %s\n", "", bad[k].c_str());
      }
    }
  } catch (const std::exception& e) {
    std::printf("FAIL %s\n", e.what());
    return 1;
  }
  return failures ? 1 : 0;
}
