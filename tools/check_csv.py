#!/usr/bin/env python3
"""Independent legality check of a vprof CSV profile against its JSON request.

Shares no code with vprof. Applies the rules of the contract (proto/vprof/v1/vprof.proto):
v >= 0; max(v_k, v_k+1) <= the lowest speed limit on [s_k, s_k+1] (distance recomputed here
from t and v by the trapezoid rule, and compared with the CSV's s column); accelerations and
jerks within range, including the jerk into the first acceleration (from start_acceleration)
and out of the last (into end_acceleration); v_0, v_N as requested; |s_N - L| <= end_tolerance;
no sample beyond L + end_tolerance; no crawl: no sample k < N at which the profile could
already end (within end_tolerance of L, at the end velocity, and the jerk from the acceleration
before it into end_acceleration within range); every t, s and v a finite number (a NaN passes
every comparison). Relative tolerance 1e-9.

usage: check_csv.py REQUEST.json PROFILE.csv   (exit 0 legal, 1 illegal, 2 bad input)
"""
import csv, json, math, sys

def main():
    if len(sys.argv) != 3:
        print(__doc__); return 2
    raw = json.load(open(sys.argv[1]))
    # proto3 JSON: a field may be spelled as in the .proto (snake_case) or in lowerCamelCase
    snake = lambda k: "".join("_" + c.lower() if c.isupper() else c for c in k)
    req = {snake(k): x for k, x in raw.items()}
    rows = list(csv.DictReader(open(sys.argv[2])))
    if not rows or list(rows[0].keys()) != ["t", "s", "v", "a", "j"]:
        print("bad CSV header: want t,s,v,a,j"); return 2
    t = [float(r["t"]) for r in rows]; v = [float(r["v"]) for r in rows]; s_csv = [float(r["s"]) for r in rows]
    bad_numbers = [f"row {k + 1}: {name}={x}" for k in range(len(rows)) for name, x in (("t", t[k]), ("s", s_csv[k]), ("v", v[k]))
                   if not math.isfinite(x)]
    if bad_numbers:
        print(f"ILLEGAL: {len(bad_numbers)} value(s) not finite"); [print("  " + b) for b in bad_numbers[:10]]; return 1
    g = lambda k, d=0.0: float(req.get(k, d) or d)
    # the contract's default end tolerance: 1 cm, or a tenth of a route shorter than 10 cm
    L = g("route_length"); tol = g("end_tolerance") or min(0.01, L / 10)
    amin, amax, jmin, jmax = g("min_acceleration"), g("max_acceleration"), g("min_jerk"), g("max_jerk")
    zones = sorted((float(z.get("start_distance", z.get("startDistance", 0)) or 0), float(z["velocity"]))
                   for z in req["speed_limits"])
    eps = lambda x: 1e-9 * max(1.0, abs(x))
    bad = []
    n = len(v) - 1
    dt = t[1] - t[0] if n >= 1 else 1.0
    for k in range(n + 1):
        if abs(t[k] - k * dt) > 1e-9 * max(1, t[k]): bad.append(f"t[{k}]={t[k]} off the uniform step {dt}")
    s = [0.0]
    for k in range(n): s.append(s[-1] + (v[k] + v[k + 1]) * dt / 2)
    for k in range(n + 1):
        if abs(s[k] - s_csv[k]) > 1e-6 * max(1, s[k]): bad.append(f"s[{k}]={s_csv[k]} but the trapezoid gives {s[k]}")
        if v[k] < -eps(0): bad.append(f"v[{k}]={v[k]} < 0")
    def lowest(a, b):
        # the first zone also covers a distance a rounding error before the route's start
        lims = [lim for i, (st, lim) in enumerate(zones)
                if (st <= b or i == 0) and (i + 1 == len(zones) or zones[i + 1][0] > a)]
        return min(lims)
    for k in range(n):
        top, lim = max(v[k], v[k + 1]), lowest(s[k], s[k + 1])
        if top > lim + eps(lim): bad.append(f"step {k}: {top} m/s above the limit {lim} on [{s[k]}, {s[k+1]}]")
    acc = [(v[k + 1] - v[k]) / dt for k in range(n)]
    for k, a in enumerate(acc):
        if a > amax + eps(amax) or a < amin - eps(amin): bad.append(f"a[{k}]={a} outside [{amin}, {amax}]")
    chain = [g("start_acceleration")] + acc + [g("end_acceleration")]
    for k in range(len(chain) - 1):
        j = (chain[k + 1] - chain[k]) / dt
        if j > jmax + eps(jmax) or j < jmin - eps(jmin): bad.append(f"jerk at {k}: {j} outside [{jmin}, {jmax}]")
    if abs(v[0] - g("start_velocity")) > eps(g("start_velocity")): bad.append(f"v0={v[0]} != start_velocity")
    if abs(v[-1] - g("end_velocity")) > eps(g("end_velocity")): bad.append(f"vN={v[-1]} != end_velocity")
    if abs(s[-1] - L) > tol + eps(L): bad.append(f"s_N={s[-1]} not within {tol} of {L}")
    if max(s) > L + tol + eps(L): bad.append(f"a sample at {max(s)} beyond {L} + {tol}")
    vE, aE = g("end_velocity"), g("end_acceleration")
    for k in range(n):
        j = (aE - chain[k]) / dt  # chain[k] is the acceleration before sample k
        if abs(s[k] - L) <= tol + eps(L) and abs(v[k] - vE) <= eps(vE) and jmin - eps(jmin) <= j <= jmax + eps(jmax):
            bad.append(f"crawl: the profile could end at sample {k} (t = {t[k]} s) but goes on until {t[-1]} s"); break
    name = req.get("name", sys.argv[1])
    if bad:
        print(f"ILLEGAL {name}: {len(bad)} violation(s)"); [print("  " + b) for b in bad[:10]]; return 1
    print(f"legal   {name}: {n + 1} samples, {t[-1]:.3f} s, {s[-1]:.4f} m")
    return 0

if __name__ == "__main__":
    sys.exit(main())
