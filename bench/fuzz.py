#!/usr/bin/env python3
"""Fuzz `vprof serve` with mutated frames (outside CI).

    python3 bench/fuzz.py --daemon PATH_TO_VPROF [--frames 100000] [--seed 1]
    python3 bench/fuzz.py --port 7450 ...        (an already running daemon; crashes are
                                                  then seen as refused connections only)

Starts `PATH serve --port 0 --quiet --max-frame-bytes 65536`, sends mutated Request frames
(bit flips, byte insertions/deletions, truncations, splices, random varints, random
bytes) pipelined in batches, and, in about 2 % of batches, a broken frame (bad or
oversized length prefix, truncated frame) after which the daemon closes the connection.
Reports how many frames were answered, by outcome, and whether the daemon survived:
"alive, N errors answered, 0 crashes".
"""
internal_samples = []
import argparse
import collections
import os
import random
import re
import socket
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "clients", "python"))
from vprof_client import load_cases, pb, read_frame, request_from_json  # noqa: E402
from google.protobuf.internal.encoder import _VarintBytes  # noqa: E402


def seeds(cases_path):
    out = [pb.Request(request_id=1, ping=pb.Ping(payload="fuzz ✓")).SerializeToString(),
           pb.Request(request_id=2).SerializeToString()]
    for i, (name, obj) in enumerate(load_cases(cases_path)[:7], start=3):
        req = pb.Request(request_id=i)
        req.profile.CopyFrom(request_from_json(obj, request_id=i))
        req.profile.time_budget = 0.05
        out.append(req.SerializeToString())
    c = pb.Request(request_id=20)
    c.compress.recording.time.extend([0, 0.1, 0.2])
    c.compress.recording.x.extend([0, 1, 2])
    out.append(c.SerializeToString())
    return out


def mutate(rng, data, pool):
    b = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        op = rng.randrange(8)
        if op == 0 and b:                          # bit flip
            i = rng.randrange(len(b)); b[i] ^= 1 << rng.randrange(8)
        elif op == 1 and b:                        # random byte
            b[rng.randrange(len(b))] = rng.randrange(256)
        elif op == 2:                              # insert bytes
            i = rng.randint(0, len(b)); b[i:i] = os.urandom(rng.randint(1, 8))
        elif op == 3 and b:                        # delete a range
            i = rng.randrange(len(b)); del b[i:i + rng.randint(1, 8)]
        elif op == 4 and b:                        # truncate
            del b[rng.randrange(len(b)):]
        elif op == 5:                              # splice with another seed
            o = rng.choice(pool); i = rng.randint(0, len(b)); j = rng.randint(0, len(o))
            b = b[:i] + o[j:]
        elif op == 6:                              # random varint somewhere
            i = rng.randint(0, len(b)); b[i:i] = _VarintBytes(rng.getrandbits(rng.choice([7, 14, 32, 63])))
        else:                                      # entirely random body
            b = bytearray(os.urandom(rng.randint(0, 64)))
    return bytes(b)


def broken_frame(rng, body):
    k = rng.randrange(3)
    if k == 0:
        return b"\xff" * 11                                  # varint too long
    if k == 1:
        return _VarintBytes(rng.randint(65537, 1 << 40))     # above --max-frame-bytes
    return _VarintBytes(len(body) + 10) + body               # truncated (then we stop sending)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--daemon")
    ap.add_argument("--host", default="127.0.0.1")
    ap.add_argument("--port", type=int)
    ap.add_argument("--frames", type=int, default=100000)
    ap.add_argument("--batch", type=int, default=100)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cases", default=os.path.join(os.environ.get("VPROF_SHARED", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared")), "reference", "velocity-cases.json"))
    args = ap.parse_args()
    rng = random.Random(args.seed)
    pool = seeds(args.cases)

    proc = None
    host, port = args.host, args.port
    if args.daemon:
        proc = subprocess.Popen([args.daemon, "serve", "--port", "0", "--quiet", "--max-frame-bytes", "65536"],
                                stderr=subprocess.PIPE, text=True)
        m = re.search(r"listening on ([\d.]+):(\d+)", proc.stderr.readline())
        host, port = m.group(1), int(m.group(2))

    outcomes = collections.Counter()
    sent = answered = closes = crashes = 0
    t0 = time.time()
    while sent < args.frames:
        if proc is not None and proc.poll() is not None:
            crashes += 1
            break
        try:
            s = socket.create_connection((host, port), timeout=30)
        except OSError:
            crashes += 1
            break
        f = s.makefile("rb")
        n = min(args.batch, args.frames - sent)
        bodies = [mutate(rng, rng.choice(pool), pool) for _ in range(n)]
        frames = [_VarintBytes(len(b)) + b for b in bodies]
        broken = rng.random() < 0.02
        if broken:
            frames.append(broken_frame(rng, rng.choice(pool)))
        try:
            s.sendall(b"".join(frames))
            if broken:
                s.shutdown(socket.SHUT_WR)
            for _ in range(n):
                body = read_frame(f.read)
                if body is None:
                    raise EOFError("closed early")
                r = pb.Response.FromString(body)
                kind = r.WhichOneof("body")
                if kind == "error":
                    outcomes["error:" + pb.ErrorCode.Name(r.error.code)] += 1
                    if r.error.code == pb.ERROR_CODE_INTERNAL and len(internal_samples) < 5:
                        internal_samples.append(r.error.message[:300])
                elif kind == "profile" and r.profile.HasField("error"):
                    outcomes["profile-error:" + pb.ErrorCode.Name(r.profile.error.code)] += 1
                else:
                    outcomes[str(kind)] += 1
                answered += 1
            if broken:
                body = read_frame(f.read)
                if body is not None:
                    outcomes["broken-frame:" + pb.ErrorCode.Name(pb.Response.FromString(body).error.code)] += 1
                if read_frame(f.read) is None:
                    closes += 1
        except (EOFError, OSError) as e:
            outcomes["connection-lost:" + type(e).__name__] += 1
        finally:
            sent += n
            s.close()

    # still alive? a ping must be answered
    alive = False
    try:
        with socket.create_connection((host, port), timeout=10) as s:
            s.sendall(_VarintBytes(len(p := pb.Request(request_id=424242, ping=pb.Ping(payload="alive?")).SerializeToString())) + p)
            r = pb.Response.FromString(read_frame(s.makefile("rb").read))
            alive = r.request_id == 424242 and r.pong.payload == "alive?"
    except OSError:
        pass
    if proc is not None:
        if proc.poll() is not None:
            crashes += 1
        proc.terminate()
        rc = proc.wait(timeout=30)
        print("daemon exit status after SIGTERM: %d" % rc)
    errors = sum(v for k, v in outcomes.items() if "error" in k)
    print("frames sent %d, answered %d in %.1f s; broken-frame connections closed by the daemon: %d"
          % (sent, answered, time.time() - t0, closes))
    for k, v in sorted(outcomes.items()):
        print("  %-40s %d" % (k, v))
    for m in internal_samples:
        print("  INTERNAL: " + m)
    print("%s, %d errors answered, %d crashes" % ("alive" if alive else "NOT ALIVE", errors, crashes))
    return 0 if alive and crashes == 0 and answered == sent else 1


if __name__ == "__main__":
    sys.exit(main())
