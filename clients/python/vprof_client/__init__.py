"""A small client for ``vprof serve`` (length-delimited vprof.v1.Request / Response).

    from vprof_client import Client, request_from_json
    with Client.connect("127.0.0.1", 7450) as c:          # or Client.spawn("vprof")
        resp = c.profile(request_from_json(case_dict))
"""
import argparse
import json
import socket
import subprocess

from google.protobuf import json_format
from google.protobuf.internal.decoder import _DecodeVarint32
from google.protobuf.internal.encoder import _VarintBytes

from ._gen import pb

__all__ = ["pb", "Client", "request_from_json", "load_cases", "summarize", "DaemonError",
           "write_frame", "read_frame", "example_main"]


class DaemonError(Exception):
    """The daemon answered with a Response whose body is an Error."""

    def __init__(self, err):
        super().__init__("%s%s: %s" % (pb.ErrorCode.Name(err.code),
                                       " (field %s)" % err.field if err.field else "",
                                       err.message))
        self.error = err


def write_frame(write, msg_bytes):
    write(_VarintBytes(len(msg_bytes)) + msg_bytes)


def read_frame(read_exact):
    """Read one delimited frame; ``read_exact(n)`` returns exactly n bytes or b'' at EOF."""
    prefix = b""
    while True:
        b = read_exact(1)
        if not b:
            if prefix:
                raise EOFError("connection closed inside a length prefix")
            return None
        prefix += b
        if not b[0] & 0x80:
            break
        if len(prefix) >= 10:
            raise ValueError("length prefix longer than 10 bytes")
    n, _ = _DecodeVarint32(prefix, 0)
    body = read_exact(n) if n else b""
    if len(body) != n:
        raise EOFError("connection closed inside a frame")
    return body


class Client:
    """One connection (TCP or a ``vprof serve --stdio`` subprocess)."""

    def __init__(self, write, read_exact, close):
        self._write, self._read_exact, self._close = write, read_exact, close
        self._next_id = 1

    @classmethod
    def connect(cls, host="127.0.0.1", port=7450, timeout=60.0):
        s = socket.create_connection((host, port), timeout=timeout)
        s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)

        def read_exact(n):
            buf = bytearray()
            while len(buf) < n:
                chunk = s.recv(n - len(buf))
                if not chunk:
                    break
                buf += chunk
            return bytes(buf)
        return cls(s.sendall, read_exact, s.close)

    @classmethod
    def spawn(cls, vprof="vprof", extra_args=(), subcommand="serve"):
        proc = subprocess.Popen([vprof, subcommand, "--stdio", "--quiet", *extra_args],
                                stdin=subprocess.PIPE, stdout=subprocess.PIPE)

        def write(b):
            proc.stdin.write(b)
            proc.stdin.flush()

        def close():
            proc.stdin.close()
            proc.wait(timeout=30)
            proc.stdout.close()
        c = cls(write, proc.stdout.read, close)
        c.process = proc
        return c

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        self._close()

    def send(self, request):
        write_frame(self._write, request.SerializeToString())

    def receive(self):
        body = read_frame(self._read_exact)
        if body is None:
            raise EOFError("daemon closed the connection")
        resp = pb.Response()
        resp.ParseFromString(body)
        return resp

    def call(self, request):
        """Send a Request (request_id filled in when 0) and return the Response."""
        if request.request_id == 0:
            request.request_id = self._next_id
            self._next_id += 1
        try:
            self.send(request)
        except (BrokenPipeError, ConnectionResetError):
            # the daemon refused the frame (FRAME_TOO_LARGE) and closed while it was still
            # being written: its answer may be waiting; without one the send error stands
            try:
                return self._answer_to(request, self.receive())
            except Exception:
                pass
            raise
        return self._answer_to(request, self.receive())

    @staticmethod
    def _answer_to(request, resp):
        # an error about the frame itself (FRAME_TOO_LARGE, a bad length prefix) carries
        # request_id 0: the daemon never read the request's id
        if resp.request_id == 0 and resp.WhichOneof("body") == "error":
            return resp
        if resp.request_id != request.request_id:
            raise RuntimeError("response request_id %d != request %d"
                               % (resp.request_id, request.request_id))
        return resp

    def ping(self, payload=""):
        resp = self.call(pb.Request(ping=pb.Ping(payload=payload)))
        if resp.WhichOneof("body") == "error":
            raise DaemonError(resp.error)
        return resp.pong

    def profile(self, profile_request):
        req = pb.Request(request_id=profile_request.request_id)
        req.profile.CopyFrom(profile_request)
        resp = self.call(req)
        kind = resp.WhichOneof("body")
        if kind == "error":
            raise DaemonError(resp.error)
        if kind != "profile":
            raise RuntimeError("expected a profile response, got %r" % kind)
        return resp.profile

    def _body(self, field, msg, answer):
        req = pb.Request(request_id=msg.request_id)
        getattr(req, field).CopyFrom(msg)
        resp = self.call(req)
        kind = resp.WhichOneof("body")
        if kind == "error":
            raise DaemonError(resp.error)
        if kind != answer:
            raise RuntimeError("expected a %s response, got %r" % (answer, kind))
        return getattr(resp, answer)

    def compress(self, compress_request):
        """Path compression: a CompressRequest in, its CompressedPath out (check .error)."""
        return self._body("compress", compress_request, "compressed")

    def fk(self, fk_request):
        """Forward kinematics: an FkRequest in, its FkResponse out (check .error)."""
        return self._body("fk", fk_request, "fk")

    def ik(self, ik_request):
        """Inverse kinematics: an IkRequest in, its IkResponse out (check .error)."""
        return self._body("ik", ik_request, "ik")

    def select(self, select_request):
        """Robot selection: a SelectRequest in, its SelectResponse out (check .error)."""
        return self._body("select", select_request, "select")

    def plan(self, plan_request):
        """Path planning: a PlanRequest in, its PlanResponse out (check .status and .error)."""
        return self._body("plan", plan_request, "plan")


def request_from_json(obj, request_id=0):
    """A ProfileRequest from a dict with proto3 JSON field names; other keys (name, note,
    ruckig_optimal_s, ...) are ignored."""
    msg = pb.ProfileRequest()
    json_format.ParseDict(obj, msg, ignore_unknown_fields=True)
    if request_id:
        msg.request_id = request_id
    return msg


def load_cases(path):
    """[(name, dict)] from a request JSON file: one request, or {"cases": [...]}."""
    with open(path) as f:
        data = json.load(f)
    if isinstance(data, dict) and "cases" in data:
        return [(c.get("name", "case-%d" % i), c) for i, c in enumerate(data["cases"])]
    if isinstance(data, list):
        return [(c.get("name", "case-%d" % i), c) for i, c in enumerate(data)]
    return [(data.get("name", path), data)]


def summarize(p):
    """The summary of a ProfileResponse as a dict."""
    return {
        "duration_s": p.duration if p.duration else (p.time[-1] if p.time else 0.0),
        "distance_m": p.distance[-1] if p.distance else 0.0,
        "samples": len(p.time),
        "peak_speed_mps": max(p.velocity) if p.velocity else 0.0,
        "iterations": p.iterations,
        "converged": p.converged,
        "legal": p.legal,
        "compute_time_s": p.compute_time,
        "algorithm": pb.Algorithm.Name(p.algorithm),
        "error": (pb.ErrorCode.Name(p.error.code) + ": " + p.error.message)
                 if p.HasField("error") else "",
    }


def example_main(doc, what, run, argv=None):
    """The command line the client examples share: ``--host``, ``--port`` and ``--out``.

    ``run(client)`` sends the example's requests and yields ``(ok, response)`` for each; with
    ``--out`` the responses are written as length-delimited frames with ``compute_time`` cleared
    (it varies), for clients/run-interop.sh to compare byte for byte with the C++ example's.
    Returns the exit code: 1 when any check failed.
    """
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--host", default="127.0.0.1")
    ap.add_argument("--port", type=int, default=7450)
    ap.add_argument("--out", help="write the %s responses (compute_time cleared) here" % what)
    args = ap.parse_args(argv)
    failures = 0
    frames = []
    with Client.connect(args.host, args.port) as c:
        for ok, r in run(c):
            failures += 0 if ok else 1
            r.compute_time = 0
            frames.append(r.SerializeToString())
    if args.out:
        with open(args.out, "wb") as f:
            for b in frames:
                write_frame(f.write, b)
    return 1 if failures else 0
