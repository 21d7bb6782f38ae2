"""Write bare ProfileRequest files (NAME.pb) from a request JSON file (one request or
{"cases": [...]}, proto3 JSON names, extra keys ignored), with protoc-generated code.

    python3 clients/make_examples.py ../shared/reference/velocity-cases.json OUTDIR
"""
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "python"))
from vprof_client import load_cases, request_from_json  # noqa: E402


def main(src, outdir):
    os.makedirs(outdir, exist_ok=True)
    for i, (name, obj) in enumerate(load_cases(src), start=1):
        safe = re.sub(r"[^A-Za-z0-9_.-]", "_", name)
        with open(os.path.join(outdir, safe + ".pb"), "wb") as f:
            f.write(request_from_json(obj, request_id=i).SerializeToString())
        print(os.path.join(outdir, safe + ".pb"))


if __name__ == "__main__":
    main(*sys.argv[1:3])
