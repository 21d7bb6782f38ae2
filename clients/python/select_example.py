"""Robot selection against a running ``vprof serve``: which of the UR5, the ABB IRB 140 and the
Franka Panda can reach four targets in a small cell (a floor and a box given in millimetres) with a
4 kg payload and 1 cm clearance; and a request with two mistakes.

    python3 clients/python/select_example.py --port PORT [--out RESPONSES.bin]

The targets are the UR5's tool poses at three joint vectors (asked of the daemon by FK) and one
3 m away. It prints the ranking and checks what the daemon says: the Panda (rated 3 kg) is
rejected by the payload filter; the far target fails with SELECT_FAILURE_REACH; every reported
joint solution, sent back through FK, reproduces its target to 1e-6 m and 1e-6 rad and has a
clearance of at least 1 cm; the bad request comes back as INVALID_ARGUMENT naming `payload` and
`targets`. With --out it writes every select response (compute_time cleared, which varies) as
length-delimited frames: the C++ example (vprof_select.cpp) writes the same requests' answers and
clients/run-interop.sh compares the two files byte for byte. Exit 1 on any failure.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from vprof_client import example_main, pb  # noqa: E402

# the same numbers as vprof_select.cpp
JOINTS = [[0.3, -1.2, 1.1, -0.5, 1.2, 0.4],
          [-0.2, -1.4, 1.5, -1.2, -1.3, 0.1],
          [0.6, -1.0, 1.3, -1.8, -1.5, 0.0]]


def cell():
    floor = pb.Mesh(vertices=[-2, -2, -0.15, 2, -2, -0.15, 2, 2, -0.15, -2, 2, -0.15],
                    triangles=[0, 1, 2, 0, 2, 3])
    # a 300 x 300 x 200 mm box behind the robot, in mm, placed by its pose
    verts = []
    for x in (-150, 150):
        for y in (-150, 150):
            for z in (-100, 100):
                verts += [x, y, z]
    tris = [0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1,
            2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3]
    box = pb.Mesh(vertices=verts, triangles=tris, scale=0.001,
                  pose=pb.Pose(x=-0.5, y=-0.4, z=0.0, qw=math.cos(0.2), qz=math.sin(0.2)))
    return [floor, box]


def requests(targets):
    """(label, SelectRequest): the same list as vprof_select.cpp builds."""
    good = pb.SelectRequest(request_id=201, environment=cell(),
                            tool_capsule=pb.Capsule(az=-0.03, radius=0.01),
                            payload=4.0, clearance=0.01, targets=targets,
                            robots=[pb.Robot(name="ur5"), pb.Robot(name="ABB IRB 140"),
                                    pb.Robot(name="franka-panda")])
    bad = pb.SelectRequest(request_id=202, payload=-1.0, clearance=0.01, robots=[pb.Robot(name="ur5")])
    return [("select cell", good), ("select bad", bad)]


def pose_error(a, b):
    dp = math.sqrt((a.x - b.x) ** 2 + (a.y - b.y) ** 2 + (a.z - b.z) ** 2)
    dot = abs(a.qw * b.qw + a.qx * b.qx + a.qy * b.qy + a.qz * b.qz)
    return dp, 2 * math.acos(min(1.0, dot))


def check_cell(c, req, r):
    ok = not r.HasField("error") and len(r.robots) == 3
    for rank, robot in enumerate(r.robots, 1):
        ok = ok and robot.rank == rank
        worst = (0.0, 0.0)
        for t, target in zip(robot.targets, req.targets):
            if t.joints:
                back = c.fk(pb.FkRequest(robot=pb.Robot(name=robot.robot), joints=t.joints)).tool
                e = pose_error(back, target)
                worst = (max(worst[0], e[0]), max(worst[1], e[1]))
                ok = ok and t.reached and t.clearance >= req.clearance and t.clearance_body != ""
            else:
                ok = ok and not t.reached and t.failure != "" and t.failure_code != pb.SELECT_FAILURE_NONE
        ok = ok and worst[0] <= 1e-6 and worst[1] <= 1e-6
        if robot.rejected:
            print("  %d %-14s rejected: %s" % (rank, robot.robot, robot.rejected))
            ok = ok and robot.robot == "franka-panda" and "payload" in robot.rejected
        else:
            far = robot.targets[-1]
            ok = ok and far.failure_code == pb.SELECT_FAILURE_REACH and robot.total == 4
            print("  %d %-14s reached %d/%d  min clearance %.1f mm (%s)  min manipulability %.4f  score %.1f"
                  "  worst FK residual %.1e m %.1e rad  %s: %s"
                  % (rank, robot.robot, robot.reached, robot.total, 1000 * robot.min_clearance,
                     robot.min_clearance_body, robot.min_manipulability, robot.score, worst[0], worst[1],
                     far.label, pb.SelectFailure.Name(far.failure_code)))
    return ok


def run(c):
    """Send the requests, check each answer; yield (ok, response)."""
    targets = [c.fk(pb.FkRequest(robot=pb.Robot(name="ur5"), joints=q)).tool for q in JOINTS]
    targets.append(pb.Pose(x=3.0, z=0.5, qx=1.0))
    for label, req in requests(targets):
        r = c.select(req)
        if label == "select bad":
            fields = sorted(e.field for e in r.errors)
            ok = r.error.code == pb.ERROR_CODE_INVALID_ARGUMENT and fields == ["payload", "targets"] \
                and "-1.0 kg" in r.error.message and not r.robots
            print("%-12s %s %s (fields %s)" % (label, "ok  " if ok else "FAIL",
                                               pb.ErrorCode.Name(r.error.code), ", ".join(fields)))
        else:
            print("%-12s" % label)
            ok = check_cell(c, req, r)
            print("%-12s %s" % ("", "ok" if ok else "FAIL"))
        yield ok, r


def main(argv=None):
    return example_main(__doc__, "select", run, argv)


if __name__ == "__main__":
    sys.exit(main())
