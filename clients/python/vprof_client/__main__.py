"""python3 -m vprof_client REQUEST.json [--host H] [--port P | --spawn PATH_TO_VPROF]

Sends each request of the file (one request object or {"cases": [...]}, proto3 JSON field
names, extra keys ignored) to ``vprof serve`` and prints a summary line per request.
Exits 1 if any request failed or produced an illegal profile.
"""
import argparse
import sys

from . import Client, DaemonError, load_cases, request_from_json, summarize


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m vprof_client", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("request", help="request JSON file")
    ap.add_argument("--host", default="127.0.0.1")
    ap.add_argument("--port", type=int, default=7450)
    ap.add_argument("--spawn", metavar="PATH_TO_VPROF",
                    help="start PATH_TO_VPROF serve --stdio instead of connecting")
    ap.add_argument("--case", action="append", help="only the case(s) with this name")
    ap.add_argument("--transport-only", action="store_true",
                    help="do not fail on illegal/empty profiles (for the stub daemon)")
    args = ap.parse_args(argv)

    cases = [(n, c) for n, c in load_cases(args.request) if not args.case or n in args.case]
    client = Client.spawn(args.spawn) if args.spawn else Client.connect(args.host, args.port)
    failures = 0
    with client:
        for i, (name, obj) in enumerate(cases, start=1):
            try:
                p = client.profile(request_from_json(obj, request_id=i))
            except DaemonError as e:
                print("%-22s ERROR %s" % (name, e))
                failures += 1
                continue
            s = summarize(p)
            ok = args.transport_only or (s["legal"] and not s["error"])
            failures += 0 if ok else 1
            print("%-22s %s duration=%.3fs distance=%.3fm samples=%d peak_speed=%.3fm/s "
                  "iterations=%d converged=%s legal=%s compute=%.1fms%s"
                  % (name, "ok  " if ok else "FAIL", s["duration_s"], s["distance_m"],
                     s["samples"], s["peak_speed_mps"], s["iterations"],
                     str(s["converged"]).lower(), str(s["legal"]).lower(),
                     s["compute_time_s"] * 1e3, (" error=" + s["error"]) if s["error"] else ""))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
