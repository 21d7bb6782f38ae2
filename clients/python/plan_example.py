"""Path planning against a running ``vprof serve``: the closed square of examples/plan-square.csv
for a UR5 (z10, v500), a move that leaves the UR5's reach, and a request with two mistakes.

    python3 clients/python/plan_example.py --port PORT [--out RESPONSES.bin]

It prints one line per request and checks what the daemon says, on its own: the square's plan is
OK, its arrays have one entry per sample (q and qd dof entries per sample, row-major), the samples
are time_step apart and the duration is the last one's time; every joint value is within the UR5's
published limits (+-360 deg) and every joint speed, by forward differences of q, within its
published 180 deg/s (src/robots/ur5.yaml); the TCP of every 20th sample, asked of the daemon by FK,
is within the 10 mm zone (+ 0.1 mm) of the waypoint polyline. The move out of reach stops with
PLAN_STATUS_OUT_OF_REACH (INFEASIBLE) between 0.3 and 0.8 m along; the bad request comes back as
INVALID_ARGUMENT naming `speed` and `waypoints`. With --out it writes every plan response
(compute_time cleared, which varies) as length-delimited frames: the C++ example (vprof_plan.cpp)
writes the same requests' answers and clients/run-interop.sh compares the two files byte for byte.
Exit 1 on any failure.
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from vprof_client import example_main, pb  # noqa: E402

SQUARE = os.path.join(HERE, "..", "..", "examples", "plan-square.csv")
LIMIT = 2 * math.pi        # rad, the UR5's +-360 deg
SPEED = math.pi            # rad/s, the UR5's 180 deg/s
ZONE = 0.01                # m, z10


def read_square():
    rows = []
    with open(SQUARE) as f:
        next(f)
        for line in f:
            if line.strip():
                rows.append([float(v) for v in line.split(",")])
    return rows


def poses(rows):
    cols = list(zip(*rows))
    return pb.Poses(time=cols[0], x=cols[1], y=cols[2], z=cols[3], qw=cols[4], qx=cols[5], qy=cols[6], qz=cols[7])


def requests():
    """(label, PlanRequest): the same list as vprof_plan.cpp builds."""
    ur5 = pb.Robot(name="ur5")
    square = pb.PlanRequest(request_id=301, waypoints=poses(read_square()), robot=ur5, speed=0.5, zone=ZONE)
    far = pb.PlanRequest(request_id=302, robot=ur5,
                         waypoints=pb.Poses(x=[0.4, 1.2], y=[0, 0], z=[0.3, 0.3], qw=[0, 0], qx=[1, 1],
                                            qy=[0, 0], qz=[0, 0]))
    bad = pb.PlanRequest(request_id=303, robot=ur5, speed=-0.5,
                         waypoints=pb.Poses(x=[0.4], y=[0], z=[0.3], qw=[0], qx=[1], qy=[0], qz=[0]))
    return [("plan square", square), ("plan far", far), ("plan bad", bad)]


def segment_distance(p, a, b):
    d = [b[i] - a[i] for i in range(3)]
    l2 = sum(x * x for x in d)
    u = 0.0 if l2 == 0 else max(0.0, min(1.0, sum((p[i] - a[i]) * d[i] for i in range(3)) / l2))
    return math.sqrt(sum((a[i] + u * d[i] - p[i]) ** 2 for i in range(3)))


def check_square(c, req, r):
    n, m = r.dof, len(r.time)
    ok = r.status == pb.PLAN_STATUS_OK and not r.HasField("error") and n == 6 and m > 100
    ok = ok and all(len(a) == m for a in (r.distance, r.velocity, r.acceleration, r.jerk))
    ok = ok and len(r.q) == m * n and len(r.qd) == m * n
    ok = ok and r.duration > 0 and r.duration == r.time[-1]
    ok = ok and all(abs(r.time[k + 1] - r.time[k] - r.time_step) < 1e-9 for k in range(m - 1))
    worst_q = max(abs(x) for x in r.q)
    worst_v = max(abs(r.q[(k + 1) * n + i] - r.q[k * n + i]) / r.time_step for k in range(m - 1) for i in range(n))
    ok = ok and worst_q <= LIMIT and worst_v <= SPEED * 1.001
    pts = [(w[1], w[2], w[3]) for w in read_square()]
    worst_tcp = 0.0
    for k in list(range(0, m, 20)) + [m - 1]:
        t = c.fk(pb.FkRequest(robot=req.robot, joints=r.q[k * n:(k + 1) * n])).tool
        d = min(segment_distance((t.x, t.y, t.z), a, b) for a, b in zip(pts, pts[1:]))
        worst_tcp = max(worst_tcp, d)
    ok = ok and worst_tcp <= ZONE + 1e-4
    print("%-12s %s %s: %d samples, dt %.3f s, duration %.3f s, route %.1f mm, %d zones, peak %.1f mm/s, "
          "largest |q| %.3f rad, joint speed %.3f rad/s, TCP off the polyline %.2f mm"
          % ("plan square", "ok  " if ok else "FAIL", pb.PlanStatus.Name(r.status), m, r.time_step, r.duration,
             1000 * r.route_length, len(r.zones), 1000 * max(r.velocity), worst_q, worst_v, 1000 * worst_tcp))
    return ok


def run(c):
    """Send the requests, check each answer; yield (ok, response)."""
    for label, req in requests():
        r = c.plan(req)
        if label == "plan square":
            ok = check_square(c, req, r)
        elif label == "plan far":
            ok = r.status == pb.PLAN_STATUS_OUT_OF_REACH and r.error.code == pb.ERROR_CODE_INFEASIBLE \
                and 0.3 < r.stop_distance < 0.8 and abs(r.stop_pose.x - (0.4 + r.stop_distance)) < 1e-9 \
                and not r.time
            print("%-12s %s %s at %.1f mm: %s" % (label, "ok  " if ok else "FAIL", pb.PlanStatus.Name(r.status),
                                                 1000 * r.stop_distance, r.error.message))
        else:
            fields = sorted(e.field for e in r.errors)
            ok = r.status == pb.PLAN_STATUS_INVALID_ARGUMENT and r.error.code == pb.ERROR_CODE_INVALID_ARGUMENT \
                and fields == ["speed", "waypoints"] and "-0.5 m/s" in r.error.message and not r.time
            print("%-12s %s %s (fields %s)" % (label, "ok  " if ok else "FAIL",
                                               pb.ErrorCode.Name(r.error.code), ", ".join(fields)))
        yield ok, r


def main(argv=None):
    return example_main(__doc__, "plan", run, argv)


if __name__ == "__main__":
    sys.exit(main())
