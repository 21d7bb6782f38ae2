"""Python client against a real `vprof serve` process.

    VPROF_DAEMON=path/to/vprof  python3 -m unittest discover -s clients/python/tests

VPROF_DAEMON is run as `VPROF_DAEMON serve ...` (the real `vprof`, or `vprof-stub-daemon`
before the merge). Set VPROF_REAL=1 when it is the real generator: the assertions marked
[real] (legal, converged profiles matching the request) only run then; the [stub]
drain test needs the stub's `sleep:` ping and only runs without VPROF_REAL.
"""
import json
import os
import re
import signal
import socket
import subprocess
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from vprof_client import Client, load_cases, pb, request_from_json, write_frame, read_frame  # noqa: E402

DAEMON = os.environ.get("VPROF_DAEMON", "vprof")
REAL = os.environ.get("VPROF_REAL") == "1"
SHARED = os.environ.get("VPROF_SHARED", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "..", "shared"))
CASES = os.environ.get("VPROF_CASES", os.path.join(SHARED, "reference", "velocity-cases.json"))


def start_daemon(*extra):
    proc = subprocess.Popen([DAEMON, "serve", "--port", "0", *extra],
                            stderr=subprocess.PIPE, text=True)
    line = proc.stderr.readline()
    m = re.search(r"listening on ([\d.]+):(\d+)", line)
    if not m:
        proc.kill()
        raise RuntimeError("daemon did not say where it listens: %r" % line)
    # keep draining its log lines so that a full pipe never blocks the daemon
    threading.Thread(target=lambda: [None for _ in proc.stderr], daemon=True).start()
    return proc, m.group(1), int(m.group(2))


class DaemonTest(unittest.TestCase):
    def setUp(self):
        self.proc, self.host, self.port = start_daemon("--max-frame-bytes", "1000000")

    def tearDown(self):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            self.proc.wait(timeout=30)

    def test_ping(self):
        with Client.connect(self.host, self.port) as c:
            pong = c.ping("héllo ✓")
            self.assertEqual(pong.payload, "héllo ✓")

    def test_every_reference_case(self):
        with Client.connect(self.host, self.port) as c:
            for i, (name, obj) in enumerate(load_cases(CASES), start=1):
                req = request_from_json(obj, request_id=1000 + i)
                p = c.profile(req)
                self.assertEqual(p.request_id, 1000 + i, name)
                if REAL:  # [real] needs the generator
                    self.assertTrue(p.legal, name)
                    self.assertTrue(p.converged, name)
                    self.assertGreater(len(p.velocity), 2, name)
                    self.assertAlmostEqual(p.velocity[0], req.start_velocity, delta=1e-9)
                    self.assertAlmostEqual(p.velocity[-1], req.end_velocity, delta=1e-9)
                    tol = req.end_tolerance or 0.01
                    self.assertLessEqual(abs(p.distance[-1] - req.route_length), tol + 1e-9, name)

    def test_extra_json_keys_are_ignored(self):
        obj = dict(load_cases(CASES)[0][1])
        self.assertIn("note", obj)
        req = request_from_json(obj)
        self.assertEqual(req.route_length, obj["route_length"])

    @unittest.skipUnless(REAL, "[real] the stub serves no kinematics")
    def test_fk_then_ik_round_trip(self):
        """[real] IK of an FK pose gives solutions that FK maps back onto it; a bad joint
        count is INVALID_ARGUMENT naming `joints`."""
        q = [0.2, -1.1, 1.3, -0.4, 1.0, 0.3]
        ur5 = pb.Robot(name="ur5")
        with Client.connect(self.host, self.port) as c:
            fk = c.fk(pb.FkRequest(robot=ur5, joints=q))
            self.assertFalse(fk.HasField("error"))
            self.assertEqual(fk.dof, 6)
            ik = c.ik(pb.IkRequest(robot=ur5, target=fk.tool, seed=q))
            self.assertEqual(ik.solver, "closed-form six-axis")
            self.assertEqual(len(ik.solutions), 1)
            for a, b in zip(ik.solutions[0].joints, q):
                self.assertAlmostEqual(a, b, places=9)
            back = c.fk(pb.FkRequest(robot=ur5, joints=ik.solutions[0].joints)).tool
            for f in ("x", "y", "z"):
                self.assertAlmostEqual(getattr(back, f), getattr(fk.tool, f), places=9)
            bad = c.fk(pb.FkRequest(robot=ur5, joints=[0, 0]))
            self.assertEqual(bad.error.code, pb.ERROR_CODE_INVALID_ARGUMENT)
            self.assertEqual(bad.error.field, "joints")

    def test_frame_too_large_then_closed(self):
        s = socket.create_connection((self.host, self.port))
        s.sendall(bytes([0x80, 0x89, 0x7a]))  # 2,000,000 > --max-frame-bytes 1000000
        f = s.makefile("rb")
        body = read_frame(f.read)
        resp = pb.Response.FromString(body)
        self.assertEqual(resp.error.code, pb.ERROR_CODE_FRAME_TOO_LARGE)
        self.assertIsNone(read_frame(f.read))  # closed
        s.close()
        with Client.connect(self.host, self.port) as c:
            self.assertEqual(c.ping("x").payload, "x")

    def test_call_too_large_returns_the_answer(self):
        # a 5 MB request written whole by Client.call: the daemon reads and drops the body it
        # refuses, so the write succeeds and call() returns FRAME_TOO_LARGE (request_id 0,
        # the daemon never read the id) instead of raising ECONNRESET from sendall
        with Client.connect(self.host, self.port) as c:
            req = pb.Request(ping=pb.Ping(payload="x" * 5_000_000))
            resp = c.call(req)
            self.assertEqual(resp.WhichOneof("body"), "error")
            self.assertEqual(resp.error.code, pb.ERROR_CODE_FRAME_TOO_LARGE)
            self.assertEqual(resp.request_id, 0)
        with Client.connect(self.host, self.port) as c:
            self.assertEqual(c.ping("after").payload, "after")

    def test_malformed_then_usable(self):
        s = socket.create_connection((self.host, self.port))
        f = s.makefile("rb")
        write_frame(s.sendall, b"\x12\x50\x01")  # profile field running past the end
        resp = pb.Response.FromString(read_frame(f.read))
        self.assertEqual(resp.error.code, pb.ERROR_CODE_MALFORMED)
        write_frame(s.sendall, pb.Request(request_id=5, ping=pb.Ping(payload="y")).SerializeToString())
        resp = pb.Response.FromString(read_frame(f.read))
        self.assertEqual((resp.request_id, resp.pong.payload), (5, "y"))
        s.close()

    def test_sigterm_exits_zero(self):
        with Client.connect(self.host, self.port) as c:
            c.ping("before")
        self.proc.send_signal(signal.SIGTERM)
        self.assertEqual(self.proc.wait(timeout=30), 0)

    @unittest.skipIf(REAL, "[stub] needs the stub's sleep: ping")
    def test_sigterm_drains_in_flight(self):
        c = Client.connect(self.host, self.port)
        c.send(pb.Request(request_id=9, ping=pb.Ping(payload="sleep:0.7")))
        time.sleep(0.2)
        self.proc.send_signal(signal.SIGTERM)
        resp = c.receive()
        self.assertEqual((resp.request_id, resp.pong.payload), (9, "sleep:0.7"))
        self.assertEqual(self.proc.wait(timeout=30), 0)
        with self.assertRaises(OSError):
            socket.create_connection((self.host, self.port), timeout=2)
        c.close()


class StdioTest(unittest.TestCase):
    def test_spawn_stdio(self):
        with Client.spawn(DAEMON) as c:
            self.assertEqual(c.ping("p").payload, "p")
            name, obj = load_cases(CASES)[0]
            p = c.profile(request_from_json(obj, request_id=42))
            self.assertEqual(p.request_id, 42)
            if REAL:  # [real]
                self.assertTrue(p.legal)
        self.assertEqual(c.process.returncode, 0)

    @unittest.skipIf(REAL, "[stub] needs the stub's sleep: ping")
    def test_stdio_sigterm_drains(self):
        c = Client.spawn(DAEMON)
        c.send(pb.Request(request_id=3, ping=pb.Ping(payload="sleep:0.5")))
        time.sleep(0.2)
        c.process.send_signal(signal.SIGTERM)
        r = c.receive()
        self.assertEqual((r.request_id, r.pong.payload), (3, "sleep:0.5"))
        self.assertEqual(c.process.wait(timeout=10), 0)


if __name__ == "__main__":
    unittest.main()
