"""Locate (and if needed generate with protoc) the Python code for proto/vprof/v1/vprof.proto.

The generated module goes to ``vprof_client/gen/`` (gitignored). It is regenerated when
missing or older than the .proto file. ``VPROF_PROTO_DIR`` overrides the proto root
(default: ``<repo>/proto``) and ``PROTOC`` the compiler (default ``protoc``).
"""
import importlib
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
GEN = os.path.join(HERE, "gen")
PROTO_ROOT = os.environ.get(
    "VPROF_PROTO_DIR", os.path.normpath(os.path.join(HERE, "..", "..", "..", "proto")))
PROTO_REL = os.path.join("vprof", "v1", "vprof.proto")


def generate(force=False):
    """Run protoc if the generated module is missing or stale. Returns its path."""
    src = os.path.join(PROTO_ROOT, PROTO_REL)
    out = os.path.join(GEN, "vprof", "v1", "vprof_pb2.py")
    stale = not os.path.exists(out) or (
        os.path.exists(src) and os.path.getmtime(src) > os.path.getmtime(out))
    if force or stale:
        if not os.path.exists(src):
            raise RuntimeError("vprof.proto not found at %s (set VPROF_PROTO_DIR)" % src)
        os.makedirs(GEN, exist_ok=True)
        subprocess.run([os.environ.get("PROTOC", "protoc"), "-I", PROTO_ROOT,
                        "--python_out=" + GEN, PROTO_REL], check=True)
    return out


def load():
    generate()
    if GEN not in sys.path:
        sys.path.insert(0, GEN)
    return importlib.import_module("vprof.v1.vprof_pb2")


pb = load()
