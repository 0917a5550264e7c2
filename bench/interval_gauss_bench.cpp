// 6x6 interval Gauss elimination: pkm_accuracy's hand-written Interval against Boost.Interval, in the same run.
//
//   (a)  pkm Interval            round in the caller's mode, step one ulp outward (Rounding.hpp); no mode switch.
//   (b)  Boost default           boost::numeric::interval<double>: rounded_math<double> =
//   save_state<rounded_arith_opp>,
//                                i.e. every operation saves the rounding mode, sets FE_UPWARD and restores it.
//   (c)  Boost hoisted           interval<double, policies<save_state_nothing<rounded_arith_opp<double>>,
//                                checking_strict<double>>>: no mode handling per operation; the caller sets
//                                FE_UPWARD once around the whole loop (rounded_arith_opp requires upward rounding).
//                                The rounding mode is per thread, so every thread (every TBB task) running such code
//                                must set it up and restore it, and no other floating-point code may run on that
//                                thread meanwhile. Stock rounded_arith_opp computes lower bounds as -((-x) op y);
//                                without -frounding-math GCC folds (-x) * y into -(x * y), exact in round-to-nearest
//                                only, which makes lower bounds of * and / wrong. The run checks every hoisted
//                                configuration on random operations and marks it UNSOUND when that happens (it
//                                does with the project's flags, GCC 12 -O3). Built by hand with -frounding-math, (c)
//                                is sound (see docs/interval-arithmetic.md for those figures).
//   (c') Boost hoisted, opaque   the same with a small policy derived from rounded_arith_opp whose negated operands
//                                pass through an empty asm statement, so that the compiler cannot fold them: sound
//                                with the project's flags (same check), same per-thread caveats as (c).
//
// Two systems A x = b, 64 random instances each:
//   case 1  A = I + E, E_ij random intervals of width ~1e-3 (centre in [-1e-3, 1e-3]), b random ~1, plain Gauss;
//   case 2  A = M +- 1e-4 |M| (M dense, non-symmetric, entries ~1, diagonally weighted: a Jacobian-like matrix),
//           C = mid(A)^-1 computed in double outside the timing; the timed solve forms C A and C b in interval
//           arithmetic and eliminates (C A) x = C b.
// Gauss elimination without pivoting (both matrices are strongly diagonally dominant, case 2 after
// preconditioning). Reported: median and minimum thread-CPU ns per solve over interleaved rounds, the ratio of the
// medians to (a), the mean relative width of the solution enclosures, and whether every enclosure contains the solution
// of the midpoint system (computed in long double).
#include <algorithm>
#include <boost/numeric/interval.hpp>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "pkm_accuracy/core/interval/Interval.hpp"

namespace {

using pkm_accuracy::interval::Interval;
namespace bi = boost::numeric;
namespace bil = boost::numeric::interval_lib;

using BoostDefault = bi::interval<double>;
using BoostHoisted =
    bi::interval<double,
                 bil::policies<bil::save_state_nothing<bil::rounded_arith_opp<double>>, bil::checking_strict<double>>>;

// rounded_arith_opp whose "down" operations hide the negated operand from the optimizer (an empty asm statement
// with the value in an SSE register), so that -((-x) op y) cannot be folded into x op y.
template <typename T>
struct OpaqueOpp : bil::rounded_arith_opp<T> {
  static T hide(T x) {
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__SSE2__))
    __asm__ volatile("" : "+x"(x));
#else
    volatile T v = x;
    x = v;
#endif
    return x;
  }
  T add_down(const T& x, const T& y) { return -this->force_rounding(hide(-x) - y); }
  T sub_down(const T& x, const T& y) { return -this->force_rounding(hide(-x) + y); }
  T mul_down(const T& x, const T& y) { return -this->force_rounding(hide(-x) * y); }
  T div_down(const T& x, const T& y) { return -this->force_rounding(hide(-x) / y); }
};
using BoostOpaque =
    bi::interval<double, bil::policies<bil::save_state_nothing<OpaqueOpp<double>>, bil::checking_strict<double>>>;

constexpr int kN = 6;

// ---- uniform access to the three interval types ------------------------------------------------------------------
template <typename I>
I make(double lo, double hi) {
  return I(lo, hi);
}
double lowerOf(const Interval& x) { return x.lower(); }
double upperOf(const Interval& x) { return x.upper(); }
template <typename I>
double lowerOf(const I& x) {
  return x.lower();
}
template <typename I>
double upperOf(const I& x) {
  return x.upper();
}

template <typename I>
struct System {
  I a[kN][kN];
  I b[kN];
};

// Gauss elimination without pivoting, then back substitution. Works on copies.
template <typename I>
void gauss(System<I> s, I x[kN]) {
  for (int k = 0; k < kN; ++k) {
    for (int i = k + 1; i < kN; ++i) {
      const I f = s.a[i][k] / s.a[k][k];
      for (int j = k + 1; j < kN; ++j) s.a[i][j] -= f * s.a[k][j];
      s.b[i] -= f * s.b[k];
    }
  }
  for (int i = kN - 1; i >= 0; --i) {
    I acc = s.b[i];
    for (int j = i + 1; j < kN; ++j) acc -= s.a[i][j] * x[j];
    x[i] = acc / s.a[i][i];
  }
}

// Preconditioned solve: x = Gauss(C A, C b) with C a point matrix.
template <typename I>
void preconditionedSolve(const System<I>& s, const double c[kN][kN], I x[kN]) {
  System<I> t;
  for (int i = 0; i < kN; ++i) {
    for (int j = 0; j < kN; ++j) {
      I acc = c[i][0] * s.a[0][j];
      for (int k = 1; k < kN; ++k) acc += c[i][k] * s.a[k][j];
      t.a[i][j] = acc;
    }
    I acc = c[i][0] * s.b[0];
    for (int k = 1; k < kN; ++k) acc += c[i][k] * s.b[k];
    t.b[i] = acc;
  }
  gauss(t, x);
}

// ---- problem instances (as double bounds, converted to each type) -----------------------------------------------
struct Instance {
  double lo[kN][kN], hi[kN][kN], blo[kN], bhi[kN];
  double c[kN][kN];      // preconditioner (used by the preconditioned case)
  long double xMid[kN];  // solution of the midpoint system
};

template <typename I>
System<I> convert(const Instance& in) {
  System<I> s;
  for (int i = 0; i < kN; ++i) {
    for (int j = 0; j < kN; ++j) s.a[i][j] = make<I>(in.lo[i][j], in.hi[i][j]);
    s.b[i] = make<I>(in.blo[i], in.bhi[i]);
  }
  return s;
}

void finishInstance(Instance* in) {
  Eigen::Matrix<long double, kN, kN> m;
  Eigen::Matrix<long double, kN, 1> v;
  Eigen::Matrix<double, kN, kN> md;
  for (int i = 0; i < kN; ++i) {
    for (int j = 0; j < kN; ++j) {
      m(i, j) = 0.5L * in->lo[i][j] + 0.5L * in->hi[i][j];
      md(i, j) = 0.5 * in->lo[i][j] + 0.5 * in->hi[i][j];
    }
    v(i) = 0.5L * in->blo[i] + 0.5L * in->bhi[i];
  }
  const Eigen::Matrix<long double, kN, 1> x = m.partialPivLu().solve(v);
  for (int i = 0; i < kN; ++i) in->xMid[i] = x(i);
  const Eigen::Matrix<double, kN, kN> c = md.inverse();
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < kN; ++j) in->c[i][j] = c(i, j);
}

std::vector<Instance> identityInstances(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Instance> out(count);
  for (Instance& in : out) {
    for (int i = 0; i < kN; ++i) {
      for (int j = 0; j < kN; ++j) {
        const double centre = (i == j ? 1.0 : 0.0) + 1e-3 * u(rng), halfWidth = 0.5e-3 * (1.0 + 0.2 * u(rng));
        in.lo[i][j] = centre - halfWidth;
        in.hi[i][j] = centre + halfWidth;
      }
      const double bc = u(rng);
      in.blo[i] = bc - 1e-6;
      in.bhi[i] = bc + 1e-6;
    }
    finishInstance(&in);
  }
  return out;
}

std::vector<Instance> jacobianInstances(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Instance> out(count);
  for (Instance& in : out) {
    for (int i = 0; i < kN; ++i) {
      for (int j = 0; j < kN; ++j) {
        // a dense, non-symmetric matrix with entries ~1 and a diagonal that keeps it well conditioned
        const double centre = u(rng) + (i == j ? 3.0 : 0.0), r = 1e-4 * std::fabs(centre) + 1e-7;
        in.lo[i][j] = centre - r;
        in.hi[i][j] = centre + r;
      }
      const double bc = 2.0 * u(rng);
      in.blo[i] = bc - 1e-5;
      in.bhi[i] = bc + 1e-5;
    }
    finishInstance(&in);
  }
  return out;
}

// ---- timing ------------------------------------------------------------------------------------------------------
struct Quality {
  bool containsMidpointSolution = true;
  double meanRelativeWidth = 0.0;
};

template <typename I>
Quality quality(const std::vector<System<I>>& systems, const std::vector<Instance>& inst, bool preconditioned) {
  Quality q;
  double widthSum = 0.0;
  for (std::size_t s = 0; s < systems.size(); ++s) {
    I x[kN];
    if (preconditioned) {
      preconditionedSolve(systems[s], inst[s].c, x);
    } else {
      gauss(systems[s], x);
    }
    for (int i = 0; i < kN; ++i) {
      const long double lo = lowerOf(x[i]), hi = upperOf(x[i]);
      if (!(lo <= inst[s].xMid[i] && inst[s].xMid[i] <= hi)) q.containsMidpointSolution = false;
      widthSum += static_cast<double>((hi - lo) / (1e-300L + std::fabs(inst[s].xMid[i])));
    }
  }
  q.meanRelativeWidth = widthSum / (kN * static_cast<double>(systems.size()));
  return q;
}

// CPU time of the calling thread: robust against time slicing on a shared machine (wall-clock time is not).
double threadCpuNs() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e9 * static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec);
}

template <typename I>
double timeSolves(const std::vector<System<I>>& systems, const std::vector<Instance>& inst, bool preconditioned,
                  int reps, double* checksum) {
  double sum = 0.0;
  const double t0 = threadCpuNs();
  for (int r = 0; r < reps; ++r) {
    for (std::size_t s = 0; s < systems.size(); ++s) {
      I x[kN];
      if (preconditioned) {
        preconditionedSolve(systems[s], inst[s].c, x);
      } else {
        gauss(systems[s], x);
      }
      sum += upperOf(x[r % kN]);
    }
  }
  const double t1 = threadCpuNs();
  *checksum += sum;
  return (t1 - t0) / (static_cast<double>(reps) * systems.size());
}

// (c) needs FE_UPWARD for the whole computation, including the quality check.
struct UpwardScope {
  int saved;
  UpwardScope() : saved(std::fegetround()) { std::fesetround(FE_UPWARD); }
  ~UpwardScope() { std::fesetround(saved); }
};

// Soundness spot check of a hoisted Boost configuration as compiled here: random +, -, *, / whose exact results
// are checked with error-free transformations (in round-to-nearest, after the upward section).
template <typename B>
bool hoistedSpotCheck(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.5, 2.0);
  constexpr int kCount = 100000;
  std::vector<double> xs(kCount), ys(kCount), lo(4 * kCount), hi(4 * kCount);
  for (int i = 0; i < kCount; ++i) {
    xs[i] = u(rng) * (rng() & 1 ? 1.0 : -1.0);
    ys[i] = u(rng) * (rng() & 1 ? 1.0 : -1.0);
  }
  {
    UpwardScope up;
    for (int i = 0; i < kCount; ++i) {
      const B x(xs[i]), y(ys[i]);
      const B r[4] = {x + y, x - y, x * y, x / y};
      for (int k = 0; k < 4; ++k) {
        lo[4 * i + k] = r[k].lower();
        hi[4 * i + k] = r[k].upper();
      }
    }
  }
  for (int i = 0; i < kCount; ++i) {
    const double x = xs[i], y = ys[i];
    // exact = v + e with v the rounded-to-nearest result and e its exact error (TwoSum, FMA); for the quotient the
    // remainder x - q y, times the sign of y, has the sign of x / y - q.
    const double s = x + y, bs = s - x, es = (x - (s - bs)) + (y - bs);
    const double d = x - y, bd = d - x, ed = (x - (d - bd)) + (-y - bd);
    const double p = x * y, ep = std::fma(x, y, -p);
    const double q = x / y, rq = -std::fma(q, y, -x), eq = y > 0 ? rq : -rq;
    const double val[4] = {s, d, p, q}, err[4] = {es, ed, ep, eq};
    for (int k = 0; k < 4; ++k) {
      const double l = lo[4 * i + k], h = hi[4 * i + k];
      const bool loOk = l < val[k] || (l == val[k] && err[k] >= 0.0);
      const bool hiOk = h > val[k] || (h == val[k] && err[k] <= 0.0);
      if (!loOk || !hiOk) return false;
    }
  }
  return true;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Row {
  std::string name;
  double medianNs = 0.0, minNs = 0.0;
  Quality q;
  bool sound = true;
};

template <typename I>
std::vector<System<I>> convertAll(const std::vector<Instance>& inst) {
  std::vector<System<I>> v;
  for (const Instance& in : inst) v.push_back(convert<I>(in));
  return v;
}

// One configuration of a case: its systems, whether it needs FE_UPWARD around the computation, and its timings.
template <typename I>
struct Config {
  std::vector<System<I>> systems;
  bool upward;
  std::vector<double> times;
  double measure(const std::vector<Instance>& inst, bool pre, int reps, double* checksum) {
    if (!upward) return timeSolves(systems, inst, pre, reps, checksum);
    UpwardScope up;
    return timeSolves(systems, inst, pre, reps, checksum);
  }
  Quality check(const std::vector<Instance>& inst, bool pre) {
    if (!upward) return quality(systems, inst, pre);
    UpwardScope up;
    return quality(systems, inst, pre);
  }
};

std::vector<Row> runCase(const std::vector<Instance>& inst, bool pre, int rounds, double seconds, bool soundC,
                         bool soundOpaque, double* checksum) {
  Config<Interval> a{convertAll<Interval>(inst), false, {}};
  Config<BoostDefault> b{convertAll<BoostDefault>(inst), false, {}};
  Config<BoostHoisted> c{convertAll<BoostHoisted>(inst), true, {}};
  Config<BoostOpaque> d{convertAll<BoostOpaque>(inst), true, {}};
  // calibrate the repetitions on (a): one measurement of (a) lasts about `seconds` / 4; (b) is run 8x fewer times
  int reps = 1;
  while (a.measure(inst, pre, reps, checksum) * reps * static_cast<double>(inst.size()) < 2.5e8 * seconds) reps *= 2;
  for (int r = 0; r < rounds; ++r) {
    for (int k = 0; k < 4; ++k) {  // rotate the order to spread slow phases of the shared machine over all configs
      switch ((r + k) % 4) {
        case 0:
          a.times.push_back(a.measure(inst, pre, reps, checksum));
          break;
        case 1:
          b.times.push_back(b.measure(inst, pre, std::max(1, reps / 8), checksum));
          break;
        case 2:
          c.times.push_back(c.measure(inst, pre, reps, checksum));
          break;
        default:
          d.times.push_back(d.measure(inst, pre, reps, checksum));
          break;
      }
    }
  }
  auto row = [&](const char* name, auto& cfg, bool sound) {
    Row r;
    r.name = name;
    r.medianNs = median(cfg.times);
    r.minNs = *std::min_element(cfg.times.begin(), cfg.times.end());
    r.q = cfg.check(inst, pre);
    r.sound = sound;
    return r;
  };
  return {row("(a)  pkm Interval (any mode, 1-ulp outward)", a, true),
          row("(b)  Boost interval<double> default (per op)", b, true),
          row("(c)  Boost opp, save_state_nothing, hoisted", c, soundC),
          row("(c') Boost opaque-opp, save_state_nothing, hoisted", d, soundOpaque)};
}

void printCase(const char* title, const std::vector<Row>& rows) {
  std::printf("\n%s\n", title);
  std::printf("  %-50s %11s %11s %9s %12s %9s %8s\n", "configuration", "median ns", "min ns", "ratio", "rel. width",
              "encloses", "sound");
  for (const Row& r : rows) {
    std::printf("  %-50s %11.1f %11.1f %9.2f %12.3e %9s %8s\n", r.name.c_str(), r.medianNs, r.minNs,
                r.medianNs / rows[0].medianNs, r.q.meanRelativeWidth, r.q.containsMidpointSolution ? "yes" : "NO",
                r.sound ? "yes" : "UNSOUND");
  }
}

}  // namespace

int main() {
  std::mt19937_64 rng(20240611);
  const std::vector<Instance> ident = identityInstances(rng, 64);
  const std::vector<Instance> jac = jacobianInstances(rng, 64);
  const bool soundC = hoistedSpotCheck<BoostHoisted>(1);
  const bool soundOpaque = hoistedSpotCheck<BoostOpaque>(1);
  double checksum = 0.0;
  constexpr int kRounds = 9;
  std::printf("6x6 interval Gauss elimination: %d interleaved rounds, 64 systems per case, 1 thread\n", kRounds);
  std::printf("ratio = median ns / median ns of (a); rel. width = mean width / |midpoint solution|\n");
  std::printf("sound = 4 x 100000 random +, -, *, / under FE_UPWARD enclose the exact results (hoisted configs)\n");
  const std::vector<Row> r1 = runCase(ident, false, kRounds, 1.0, soundC, soundOpaque, &checksum);
  printCase("case 1: A = I + E, |E_ij| <= 1e-3, widths ~1e-3, plain Gauss", r1);
  const std::vector<Row> r2 = runCase(jac, true, kRounds, 1.0, soundC, soundOpaque, &checksum);
  printCase("case 2: A = M +- 1e-4 |M| (Jacobian-like), (C A) x = C b with C = mid(A)^-1, C A in the timing", r2);
  std::printf(
      "\nspeed-up of (a) (median), case 1 / case 2: vs (b) %.2fx / %.2fx, vs (c) %.2fx / %.2fx, vs (c') %.2fx / "
      "%.2fx\n",
      r1[1].medianNs / r1[0].medianNs, r2[1].medianNs / r2[0].medianNs, r1[2].medianNs / r1[0].medianNs,
      r2[2].medianNs / r2[0].medianNs, r1[3].medianNs / r1[0].medianNs, r2[3].medianNs / r2[0].medianNs);
  std::printf("project rule: prefer Boost.Interval unless the hand-written path is >= 2x faster in the same run\n");
  std::printf("(checksum %g)\n", checksum);
  return 0;
}
