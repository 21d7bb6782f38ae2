"""Golden vectors of the vprof.v1 wire format, encoded by protoc-generated Python code.

Every test/golden/NAME.json is {"note": ..., "message": "Request" | "Response" | any
vprof.v1 message name, "value": proto3 JSON with the .proto field names}. Negative zero
(and any double JSON numbers cannot carry) is written as a string, e.g. "-0"; uint64s
above 2^53 as strings. This script writes NAME.bin (the message, bare, no length prefix).

    python3 test/golden/make_golden.py                 # (re)write test/golden/*.bin
    python3 test/golden/make_golden.py --check         # regenerate into a temp dir and
                                                       # compare with the committed .bin;
                                                       # also decode each .bin back and
                                                       # compare with the JSON; exit 1 on drift
The Haskell side (test/VProf/GoldenSpec.hs) builds the same messages from the same JSON and
asserts byte equality both ways.
"""
import glob
import json
import math
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "clients", "python"))
from google.protobuf import json_format  # noqa: E402
from vprof_client import pb  # noqa: E402  (runs protoc on import when needed)


def build(desc):
    msg = getattr(pb, desc["message"])()
    json_format.ParseDict(desc["value"], msg)
    return msg


def write_all(outdir):
    names = []
    for path in sorted(glob.glob(os.path.join(HERE, "*.json"))):
        name = os.path.splitext(os.path.basename(path))[0]
        with open(path, encoding="utf-8") as f:
            desc = json.load(f)
        with open(os.path.join(outdir, name + ".bin"), "wb") as f:
            f.write(build(desc).SerializeToString())
        names.append(name)
    return names


def same_double(a, b):
    return (a == b and math.copysign(1, a) == math.copysign(1, b)) or (math.isnan(a) and math.isnan(b))


def fields_equal(m1, m2):
    """Field-by-field equality that tells -0.0 from 0.0."""
    if m1.DESCRIPTOR is not m2.DESCRIPTOR:
        return False
    f1 = dict((fd.name, v) for fd, v in m1.ListFields())
    f2 = dict((fd.name, v) for fd, v in m2.ListFields())
    if f1.keys() != f2.keys():
        return False
    for fd, v in m1.ListFields():
        w = f2[fd.name]
        vs, ws = (list(v), list(w)) if fd.label == fd.LABEL_REPEATED else ([v], [w])
        if len(vs) != len(ws):
            return False
        for a, b in zip(vs, ws):
            if fd.type == fd.TYPE_MESSAGE:
                if not fields_equal(a, b):
                    return False
            elif fd.type == fd.TYPE_DOUBLE:
                if not same_double(a, b):
                    return False
            elif a != b:
                return False
    return True


def check():
    bad = 0
    with tempfile.TemporaryDirectory() as tmp:
        for name in write_all(tmp):
            with open(os.path.join(tmp, name + ".bin"), "rb") as f:
                fresh = f.read()
            committed_path = os.path.join(HERE, name + ".bin")
            if not os.path.exists(committed_path):
                print("MISSING %s.bin" % name)
                bad += 1
                continue
            with open(committed_path, "rb") as f:
                committed = f.read()
            with open(os.path.join(HERE, name + ".json"), encoding="utf-8") as f:
                desc = json.load(f)
            want = build(desc)
            decoded = getattr(pb, desc["message"]).FromString(committed)
            if fresh != committed:
                print("DRIFT   %s.bin: protoc's Python now writes different bytes" % name)
                bad += 1
            elif not fields_equal(decoded, want):
                print("DECODE  %s.bin does not decode to its JSON value" % name)
                bad += 1
            else:
                print("ok      %s.bin (%d bytes)" % (name, len(committed)))
    return bad


if __name__ == "__main__":
    if "--check" in sys.argv[1:]:
        sys.exit(1 if check() else 0)
    for n in write_all(HERE):
        print("wrote", n + ".bin")
