"""Path compression against a running ``vprof serve``: the TUM recording freiburg1_xyz (3,000
samples, ../shared/data) compressed to 90 waypoints and to a 5 mm tolerance, and a recording whose
times go back and a request for one waypoint.

    python3 clients/python/compress_example.py --port PORT [--recording FILE] [--out RESPONSES.bin]

It prints one line per request and checks what the daemon says, on its own: the 90-point path has
90 waypoints, strictly increasing times from the first sample's to the last's and the first and
last sample's positions (the ends pinned); its position RMSE and largest error, recomputed here
from the recording and the path interpolated linearly in time at every sample time, agree with the
daemon's metrics to 1e-9 m; the tolerance path's recomputed largest error is within 5 mm with
fewer than a tenth of the samples. The time going back is INVALID_ARGUMENT naming
`recording.time`; one waypoint is INVALID_ARGUMENT naming `points`. With --out it writes every
response (compute_time cleared, which varies) as length-delimited frames: the C++ example
(vprof_compress.cpp) writes the same requests' answers and clients/run-interop.sh compares the two
files byte for byte. Exit 1 on any failure.
"""
import bisect
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from vprof_client import example_main, pb  # noqa: E402

SHARED = os.environ.get("VPROF_SHARED", os.path.join(HERE, "..", "..", "..", "shared"))
RECORDING = os.path.join(SHARED, "data", "freiburg1_xyz-groundtruth.txt")
TOLERANCE = 0.005  # m


def read_tum(path):
    """Poses from a TUM trajectory: `time tx ty tz qx qy qz qw` a line, `#` comments."""
    rows = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                rows.append([float(v) for v in line.split()])
    c = list(zip(*rows))
    return pb.Poses(time=c[0], x=c[1], y=c[2], z=c[3], qx=c[4], qy=c[5], qz=c[6], qw=c[7])


def requests(recording):
    """(label, CompressRequest): the same list as vprof_compress.cpp builds."""
    back = pb.Poses(time=[0, 1, 0.5], x=[0, 0.1, 0.2], y=[0] * 3, z=[0] * 3,
                    qw=[1] * 3, qx=[0] * 3, qy=[0] * 3, qz=[0] * 3)
    one = pb.Poses(time=[0, 1, 2], x=[0, 0.1, 0.2], y=[0] * 3, z=[0] * 3,
                   qw=[1] * 3, qx=[0] * 3, qy=[0] * 3, qz=[0] * 3)
    return [("compress 90", pb.CompressRequest(request_id=401, recording=recording, points=90)),
            ("compress 5mm", pb.CompressRequest(request_id=402, recording=recording, tolerance=TOLERANCE)),
            ("compress back", pb.CompressRequest(request_id=403, recording=back)),
            ("compress one", pb.CompressRequest(request_id=404, recording=one, points=1))]


def position_errors(rec, path):
    """The time-synchronous position error at every sample: the path's waypoints interpolated
    linearly in time."""
    errs = []
    for i, t in enumerate(rec.time):
        j = min(max(bisect.bisect_right(path.time, t) - 1, 0), len(path.time) - 2)
        t0, t1 = path.time[j], path.time[j + 1]
        u = (t - t0) / (t1 - t0)
        d = [(1 - u) * a[j] + u * a[j + 1] - b[i]
             for a, b in ((path.x, rec.x), (path.y, rec.y), (path.z, rec.z))]
        errs.append(math.sqrt(sum(v * v for v in d)))
    return errs


def run_with(recording):
    def run(c):
        for label, req in requests(recording):
            r = c.compress(req)
            if label in ("compress back", "compress one"):
                field = "recording.time" if label == "compress back" else "points"
                ok = r.HasField("error") and r.error.code == pb.ERROR_CODE_INVALID_ARGUMENT \
                    and r.error.field == field
                print("%-14s %s %s (field %s)" % (label, "ok  " if ok else "FAIL",
                                                  pb.ErrorCode.Name(r.error.code), r.error.field))
            else:
                p, m = r.path, r.metrics
                errs = position_errors(req.recording, p) if len(p.time) >= 2 else [math.inf]
                rmse = math.sqrt(sum(e * e for e in errs) / len(errs))
                worst = max(errs)
                ok = not r.HasField("error") \
                    and all(a < b for a, b in zip(p.time, p.time[1:])) \
                    and p.time[0] == req.recording.time[0] and p.time[-1] == req.recording.time[-1] \
                    and abs(rmse - m.position_rmse) <= 1e-9 and abs(worst - m.position_max) <= 1e-9
                if label == "compress 90":
                    ends = [(p.x[k], p.y[k], p.z[k]) == (req.recording.x[i], req.recording.y[i], req.recording.z[i])
                            for k, i in ((0, 0), (-1, -1))]
                    ok = ok and len(p.time) == 90 and all(ends)
                else:
                    ok = ok and worst <= TOLERANCE + 1e-12 and 10 * len(p.time) < len(req.recording.time)
                print("%-14s %s %d samples -> %d points, position RMSE %.4f mm (recomputed %.4f), max %.4f mm"
                      % (label, "ok  " if ok else "FAIL", len(req.recording.time), len(p.time),
                         m.position_rmse * 1e3, rmse * 1e3, worst * 1e3))
            yield ok, r
    return run


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    path = RECORDING
    if "--recording" in argv:
        i = argv.index("--recording")
        path = argv[i + 1]
        del argv[i:i + 2]
    return example_main(__doc__, "compression", run_with(read_tum(path)), argv)


if __name__ == "__main__":
    sys.exit(main())
