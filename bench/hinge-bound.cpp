// A lower bound on the time-synchronous position SSE of any path of k waypoints that is
// linear in time between them (and so continuous), tighter than the floor of k-1 free lines:
// the path's segments are paired (1-2, 3-4, ...); each pair is a "hinge", two lines in time
// that meet at one knot, and the pairs need not meet each other. The samples of a pair form a
// consecutive group whose error is at least that of its best hinge, so the least sum of
// best-hinge errors over partitions into the pairs' groups (dynamic program) bounds every
// such path from below. With k-1 odd one segment stays a single line, first or last; both
// patterns are bounds and the larger is reported. The hinge's knot is optimised over the
// continuum: for a knot between samples s-1 and s the error is R0 - N(tau)/D(tau) with N, D
// quadratics in tau (R0: the group's line fit), whose maximum on the interval is at an end or
// at a root of a quadratic. Exact up to rounding; O(n^3) time, O(n^2) memory (floats).
// Part of bench/compare-compress (a baseline, not vprof's own code).
//
//   hinge-bound FILE K [K ...]     FILE: lines "t x y z" (times strictly increasing)
// prints one JSON object: {"n": n, "bounds": {"K": {"floor_sse": .., "hinge_sse": ..}, ..}}
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>
#include <algorithm>

int main(int argc, char** argv) {
  if (argc < 3) { std::fprintf(stderr, "usage: hinge-bound FILE K [K ...]\n"); return 2; }
  FILE* f = std::fopen(argv[1], "r");
  if (!f) { std::perror(argv[1]); return 2; }
  std::vector<double> T, X[3];
  double t, x, y, z;
  while (std::fscanf(f, "%lf %lf %lf %lf", &t, &x, &y, &z) == 4) {
    T.push_back(t); X[0].push_back(x); X[1].push_back(y); X[2].push_back(z);
  }
  std::fclose(f);
  const int n = (int)T.size();
  for (int i = 1; i < n; i++) if (!(T[i] > T[i - 1])) { std::fprintf(stderr, "times not increasing at %d\n", i); return 2; }
  std::vector<float> L((size_t)n * n, 0.f), H((size_t)n * n, 0.f);
  #pragma omp parallel
  {
    std::vector<double> c1(n + 1), ct(n + 1), ctt(n + 1), cy[3], cty[3], cyy(n + 1);
    for (int c = 0; c < 3; c++) { cy[c].assign(n + 1, 0); cty[c].assign(n + 1, 0); }
    #pragma omp for schedule(dynamic, 8)
    for (int a = 0; a < n; a++) {
      // cumulative sums from sample a, time and positions relative to sample a's
      const double t0 = T[a];
      c1[0] = ct[0] = ctt[0] = cyy[0] = 0;
      for (int c = 0; c < 3; c++) cy[c][0] = cty[c][0] = 0;
      for (int m = 0; a + m < n; m++) {
        const double tt = T[a + m] - t0;
        c1[m + 1] = c1[m] + 1; ct[m + 1] = ct[m] + tt; ctt[m + 1] = ctt[m] + tt * tt;
        double yy = 0;
        for (int c = 0; c < 3; c++) {
          const double v = X[c][a + m] - X[c][a];
          cy[c][m + 1] = cy[c][m] + v; cty[c][m + 1] = cty[c][m] + tt * v; yy += v * v;
        }
        cyy[m + 1] = cyy[m] + yy;
      }
      for (int b = a; b < n; b++) {
        const int m = b - a + 1;
        const double N = c1[m], St = ct[m], Stt = ctt[m];
        const double det = N * Stt - St * St;
        double Sy[3], Sty[3];
        for (int c = 0; c < 3; c++) { Sy[c] = cy[c][m]; Sty[c] = cty[c][m]; }
        // line fit SSE
        double R0 = cyy[m];
        for (int c = 0; c < 3; c++) {
          R0 -= Sy[c] * Sy[c] / N;
          if (m >= 2 && det > 0) { const double C = Sty[c] - St * Sy[c] / N; R0 -= C * C / (Stt - St * St / N); }
        }
        R0 = std::max(R0, 0.0);
        L[(size_t)a * n + b] = (float)R0;
        double best = R0;  // a knot outside the group: one line
        if (m >= 3 && det > 0) {
          auto proj = [&](double u1, double ut, double v1, double vt) {
            return (u1 * v1 * Stt - (u1 * vt + ut * v1) * St + ut * vt * N) / det;
          };
          for (int s = a + 1; s <= b; s++) {
            const int l = s - a;  // samples a .. s-1 on the left of the knot
            const double NL = c1[l], Lt = ct[l], Ltt = ctt[l];
            const double G = Ltt - proj(Lt, Ltt, Lt, Ltt);
            const double M = Lt - proj(Lt, Ltt, NL, Lt);
            const double E = NL - proj(NL, Lt, NL, Lt);
            double AA = 0, AB = 0, BB = 0;
            for (int c = 0; c < 3; c++) {
              const double A = cty[c][l] - proj(Sy[c], Sty[c], Lt, Ltt);
              const double B = cy[c][l] - proj(Sy[c], Sty[c], NL, Lt);
              AA += A * A; AB += A * B; BB += B * B;
            }
            const double lo = T[s - 1] - t0, hi = T[s] - t0;
            auto gain = [&](double tau) {
              const double D = G - 2 * tau * M + tau * tau * E;
              const double Nn = AA - 2 * tau * AB + tau * tau * BB;
              return D > 1e-14 * (G + tau * tau * E) && D > 0 ? Nn / D : 0.0;
            };
            double g = std::max(gain(lo), gain(hi));
            const double q2 = AB * E - BB * M, q1 = BB * G - AA * E, q0 = AA * M - AB * G;
            if (std::fabs(q2) > 1e-300) {
              const double disc = q1 * q1 - 4 * q2 * q0;
              if (disc >= 0) {
                const double sq = std::sqrt(disc);
                const double r1 = (-q1 - sq) / (2 * q2), r2 = (-q1 + sq) / (2 * q2);
                if (r1 > lo && r1 < hi) g = std::max(g, gain(r1));
                if (r2 > lo && r2 < hi) g = std::max(g, gain(r2));
              }
            } else if (std::fabs(q1) > 1e-300) {
              const double r = -q0 / q1;
              if (r > lo && r < hi) g = std::max(g, gain(r));
            }
            best = std::min(best, R0 - g);
          }
        }
        H[(size_t)a * n + b] = (float)std::max(best, 0.0);
      }
    }
  }
  // the least sum of group costs over consecutive groups of the given kinds (groups may be empty)
  auto dp = [&](const std::vector<int>& kinds) {
    std::vector<double> prev(n + 1, INFINITY), cur(n + 1);
    prev[0] = 0;
    for (int kind : kinds) {
      const std::vector<float>& C = kind ? H : L;
      for (int b = 0; b <= n; b++) {
        double bst = prev[b];
        for (int a = 0; a < b; a++) {
          const double v = prev[a] + (double)C[(size_t)a * n + b - 1];
          if (v < bst) bst = v;
        }
        cur[b] = bst;
      }
      prev.swap(cur);
    }
    return prev[n];
  };
  std::printf("{\"n\": %d, \"bounds\": {", n);
  for (int i = 2; i < argc; i++) {
    const int k = std::atoi(argv[i]), segs = k - 1;
    std::vector<int> lines(segs, 0), p1, p2;
    for (int j = 0; j < segs / 2; j++) p1.push_back(1);
    p2 = p1;
    if (segs % 2) { p1.push_back(0); p2.insert(p2.begin(), 0); }
    else if (segs >= 2) { p2.pop_back(); p2.insert(p2.begin(), 0); p2.push_back(0); }  // shifted pairing
    const double fl = dp(lines), h = std::max(dp(p1), dp(p2));
    std::printf("%s\"%d\": {\"floor_sse\": %.12g, \"hinge_sse\": %.12g}", i > 2 ? ", " : "", k, fl, h);
  }
  std::printf("}}\n");
  return 0;
}
