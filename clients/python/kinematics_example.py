"""FK and IK against a running ``vprof serve``: a library robot (UR5, closed form) and the
Franka Panda (numerical), and an inline URDF robot.

    python3 clients/python/kinematics_example.py --port PORT [--out RESPONSES.bin]

For each request it prints one line and checks what the daemon says: FK gives a unit
quaternion; every IK solution, sent back through FK, reproduces the target to 1e-6 m and
1e-6 rad. With --out it writes every response (compute_time cleared, which varies) as
length-delimited frames: the C++ example writes the same requests' answers, and
clients/run-interop.sh compares the two files byte for byte. Exit 1 on any failure.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from vprof_client import example_main, pb  # noqa: E402

URDF = """<robot name="two-axis">
  <link name="base"/><link name="upper"/><link name="tool"/>
  <joint name="turn" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="2"/></joint>
  <joint name="lift" type="prismatic"><parent link="upper"/><child link="tool"/>
    <origin xyz="0.4 0 0"/><axis xyz="0 0 1"/><limit lower="0" upper="0.5" velocity="0.5"/></joint>
</robot>"""


def requests():
    """(label, FkRequest or IkRequest): the same list as vprof_kinematics.cpp builds."""
    out = []
    ur5 = pb.Robot(name="ur5")
    out.append(("fk ur5", pb.FkRequest(request_id=101, robot=ur5,
                                       joints=[0.3, -1.2, 1.1, -0.5, 1.2, 0.4], link_frames=True)))
    target = pb.Pose(x=0.4, y=-0.1, z=0.3, qw=0.0, qx=1.0, qy=0.0, qz=0.0)
    out.append(("ik ur5 all", pb.IkRequest(request_id=102, robot=ur5, target=target, all_solutions=True)))
    panda = pb.Robot(name="franka-panda")
    pt = pb.Pose(x=0.5, y=0.1, z=0.4, qw=0.0, qx=1.0, qy=0.0, qz=0.0)
    out.append(("ik panda", pb.IkRequest(request_id=103, robot=panda, target=pt,
                                         seed=[0, -0.5, 0, -2.0, 0, 1.6, 0.8])))
    inline = pb.Robot(urdf=URDF, tip_link="tool")
    out.append(("fk urdf", pb.FkRequest(request_id=104, robot=inline, joints=[0.5, 0.2])))
    out.append(("ik urdf", pb.IkRequest(request_id=105, robot=inline,
                                        target=pb.Pose(x=0.4 * math.cos(0.5), y=0.4 * math.sin(0.5),
                                                       z=0.5, qw=math.cos(0.25), qz=math.sin(0.25)))))
    out.append(("ik bad", pb.IkRequest(request_id=106, robot=ur5,
                                       target=pb.Pose(x=0.4, qw=0.5))))
    return out


def pose_error(a, b):
    dp = math.sqrt((a.x - b.x) ** 2 + (a.y - b.y) ** 2 + (a.z - b.z) ** 2)
    dot = abs(a.qw * b.qw + a.qx * b.qx + a.qy * b.qy + a.qz * b.qz)
    return dp, 2 * math.acos(min(1.0, dot))


def run(c):
    """Send the requests, check each answer; yield (ok, response)."""
    for label, req in requests():
        if isinstance(req, pb.FkRequest):
            r = c.fk(req)
            n = math.sqrt(r.tool.qw ** 2 + r.tool.qx ** 2 + r.tool.qy ** 2 + r.tool.qz ** 2)
            ok = not r.HasField("error") and abs(n - 1) < 1e-12 and len(r.jacobian) == 6 * r.dof
            print("%-12s %s tool=(%.6f %.6f %.6f) manipulability=%.6g frames=%d"
                  % (label, "ok  " if ok else "FAIL", r.tool.x, r.tool.y, r.tool.z,
                     r.manipulability, len(r.link_frames)))
        else:
            r = c.ik(req)
            if label == "ik bad":
                ok = r.HasField("error") and r.error.field == "target" \
                    and r.error.code == pb.ERROR_CODE_INVALID_ARGUMENT
                print("%-12s %s %s (field %s)" % (label, "ok  " if ok else "FAIL",
                                                  pb.ErrorCode.Name(r.error.code), r.error.field))
            else:
                worst = (0.0, 0.0)
                for s in r.solutions:
                    back = c.fk(pb.FkRequest(robot=req.robot, joints=s.joints)).tool
                    e = pose_error(back, req.target)
                    worst = (max(worst[0], e[0]), max(worst[1], e[1]))
                ok = not r.HasField("error") and len(r.solutions) > 0 \
                    and worst[0] <= 1e-6 and worst[1] <= 1e-6
                print("%-12s %s solver=%s solutions=%d worst FK residual %.1e m %.1e rad%s"
                      % (label, "ok  " if ok else "FAIL", r.solver, len(r.solutions), worst[0], worst[1],
                         (" error=" + r.error.message) if r.HasField("error") else ""))
        yield ok, r


def main(argv=None):
    return example_main(__doc__, "FK and IK", run, argv)


if __name__ == "__main__":
    sys.exit(main())
