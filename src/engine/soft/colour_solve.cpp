// See colour_solve.hpp. A lane group is a GCC/Clang vector extension of doubles: four
// (one AVX register) where the CPU has AVX2, two (one SSE2 register, the x86-64 baseline)
// otherwise; the width is chosen once, at the first call. Lanes compute the same operations
// whatever the width, so both give the same bits.
#include "engine/soft/colour_solve.hpp"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstring>

// The lane types never cross a call that is not inlined, so the ABI GCC warns about (how a
// 32-byte vector is passed without AVX) never applies.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace millwear::soft {

namespace {

typedef double f64x4 __attribute__((vector_size(4 * sizeof(double))));
typedef long long i64x4 __attribute__((vector_size(4 * sizeof(long long))));
typedef double f64x2 __attribute__((vector_size(2 * sizeof(double))));
static_assert(kLanes == 4, "a chunk is one f64x4 or two f64x2");
static_assert(sizeof(Body) == 64 && offsetof(Body, vx) == 0 && offsetof(Body, w) == 16 &&
                  offsetof(Body, dpy) == 32 && offsetof(Body, ii) == 48 && offsetof(Body, radius) == 56,
              "a body is loaded in halves of four doubles or quarters of two");

#define MW_INLINE inline __attribute__((always_inline))

template <class V>
constexpr int width() {
  return sizeof(V) / sizeof(double);
}
template <class V>
MW_INLINE V load(const double* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <class V>
MW_INLINE void store(double* p, V v) {
  std::memcpy(p, &v, sizeof v);
}
template <class V>
MW_INLINE V splat(double x) {
  V v;
  for (int l = 0; l < width<V>(); ++l) v[l] = x;
  return v;
}
// std::max and std::clamp lane by lane, with their exact semantics (which operand is
// returned on ties and signed zeros), so that a lane is bit for bit the serial row.
template <class V>
MW_INLINE V vmax(V a, V b) {
  return a < b ? b : a;
}
template <class V>
MW_INLINE V vclamp(V v, V lo, V hi) {
  return v < lo ? lo : (hi < v ? hi : v);
}

// One side (a or b) of a lane group: its bodies' state, a field per vector.
template <class V>
struct Side {
  V vx, vy, w, dpx, dpy, im, ii, radius;
};

// Four rows of four doubles in, their four columns out.
MW_INLINE void transpose(f64x4& r0, f64x4& r1, f64x4& r2, f64x4& r3) {
  const i64x4 even = {0, 4, 2, 6}, odd = {1, 5, 3, 7}, low = {0, 1, 4, 5}, high = {2, 3, 6, 7};
  const f64x4 t0 = __builtin_shuffle(r0, r1, even), t1 = __builtin_shuffle(r0, r1, odd);
  const f64x4 t2 = __builtin_shuffle(r2, r3, even), t3 = __builtin_shuffle(r2, r3, odd);
  r0 = __builtin_shuffle(t0, t2, low);
  r1 = __builtin_shuffle(t1, t3, low);
  r2 = __builtin_shuffle(t0, t2, high);
  r3 = __builtin_shuffle(t1, t3, high);
}
// Two rows of two doubles in, their two columns out.
MW_INLINE void transpose(f64x2& r0, f64x2& r1) {
  typedef long long i64x2 __attribute__((vector_size(2 * sizeof(long long))));
  const f64x2 t0 = __builtin_shuffle(r0, r1, i64x2{0, 2});
  r1 = __builtin_shuffle(r0, r1, i64x2{1, 3});
  r0 = t0;
}

// Each body is a few aligned loads and a transpose, not eight scalar loads and inserts.
MW_INLINE void gather(const Body* body, const int* idx, Side<f64x4>& s) {
  f64x4 r0 = load<f64x4>(&body[idx[0]].vx), r1 = load<f64x4>(&body[idx[1]].vx);
  f64x4 r2 = load<f64x4>(&body[idx[2]].vx), r3 = load<f64x4>(&body[idx[3]].vx);
  transpose(r0, r1, r2, r3);
  s.vx = r0, s.vy = r1, s.w = r2, s.dpx = r3;
  f64x4 q0 = load<f64x4>(&body[idx[0]].dpy), q1 = load<f64x4>(&body[idx[1]].dpy);
  f64x4 q2 = load<f64x4>(&body[idx[2]].dpy), q3 = load<f64x4>(&body[idx[3]].dpy);
  transpose(q0, q1, q2, q3);
  s.dpy = q0, s.im = q1, s.ii = q2, s.radius = q3;
}
MW_INLINE void gather(const Body* body, const int* idx, Side<f64x2>& s) {
  const Body& b0 = body[idx[0]];
  const Body& b1 = body[idx[1]];
  f64x2 r0 = load<f64x2>(&b0.vx), r1 = load<f64x2>(&b1.vx);
  transpose(r0, r1);
  s.vx = r0, s.vy = r1;
  r0 = load<f64x2>(&b0.w), r1 = load<f64x2>(&b1.w);
  transpose(r0, r1);
  s.w = r0, s.dpx = r1;
  r0 = load<f64x2>(&b0.dpy), r1 = load<f64x2>(&b1.dpy);
  transpose(r0, r1);
  s.dpy = r0, s.im = r1;
  r0 = load<f64x2>(&b0.ii), r1 = load<f64x2>(&b1.ii);
  transpose(r0, r1);
  s.ii = r0, s.radius = r1;
}

// Writes the velocities back (dpx goes back unchanged). The lanes of a chunk have distinct
// bodies, except padding lanes, which all write the dummy.
MW_INLINE void scatter(Body* body, const int* idx, const Side<f64x4>& s) {
  f64x4 r0 = s.vx, r1 = s.vy, r2 = s.w, r3 = s.dpx;
  transpose(r0, r1, r2, r3);
  store(&body[idx[0]].vx, r0);
  store(&body[idx[1]].vx, r1);
  store(&body[idx[2]].vx, r2);
  store(&body[idx[3]].vx, r3);
}
MW_INLINE void scatter(Body* body, const int* idx, const Side<f64x2>& s) {
  f64x2 r0 = s.vx, r1 = s.vy;
  transpose(r0, r1);
  store(&body[idx[0]].vx, r0);
  store(&body[idx[1]].vx, r1);
  r0 = s.w, r1 = s.dpx;
  transpose(r0, r1);
  store(&body[idx[0]].w, r0);
  store(&body[idx[1]].w, r1);
}

// A row's anchors and effective masses, computed as build_pair_row (narrow_phase.hpp)
// computes them, operation for operation: the same bits as storing them with the row.
template <class V>
struct RowConstants {
  V alpha, beta, mn, mt, mr;
};
template <class V>
MW_INLINE V anchor(V radius, V s0) {
  return radius + splat<V>(0.5) * s0;
}
// 1 / x where x > 0, else 0 (a padding lane's dummy bodies, an inactive disk).
template <class V>
MW_INLINE V inverse_or_zero(V x) {
  const V zero = splat<V>(0.0), one = splat<V>(1.0);
  const auto positive = x > zero;
  return positive ? one / (positive ? x : one) : zero;
}
template <class V>
MW_INLINE RowConstants<V> row_constants(const Side<V>& A, const Side<V>& B, V s0) {
  RowConstants<V> k;
  k.alpha = anchor(A.radius, s0);
  k.beta = anchor(B.radius, s0);
  const V im = A.im + B.im;
  k.mn = inverse_or_zero(im);
  k.mt = inverse_or_zero(im + A.ii * k.alpha * k.alpha + B.ii * k.beta * k.beta);
  k.mr = inverse_or_zero(A.ii + B.ii);
  return k;
}

// The engine's warm start for the lanes l0 .. l0 + width of a chunk.
template <class V>
MW_INLINE void warm_start_lanes(Body* body, const WideRows& c, int l0) {
  Side<V> A, B;
  gather(body, c.a + l0, A);
  gather(body, c.b + l0, B);
  const V nx = load<V>(c.nx + l0), ny = load<V>(c.ny + l0);
  const V ln = load<V>(c.ln + l0), lt = load<V>(c.lt + l0), lr = load<V>(c.lr + l0);
  const V px = ln * nx - lt * ny, py = ln * ny + lt * nx;
  A.vx += A.im * px;
  A.vy += A.im * py;
  const V s0 = load<V>(c.s0 + l0);
  A.w += A.ii * (lr - anchor(A.radius, s0) * lt);
  B.vx -= B.im * px;
  B.vy -= B.im * py;
  B.w += B.ii * (-lr - anchor(B.radius, s0) * lt);
  scatter(body, c.a + l0, A);
  scatter(body, c.b + l0, B);
}

// The serial pass's row (contact_solver.cpp, see its comments) for the lanes l0 .. l0 +
// width of a chunk: normal (soft or speculative), friction bounded by mu times the normal impulse, rolling
// resistance bounded by its lever times it. kBias: the soft solve; otherwise the relax,
// which also sums.
template <bool kBias, class V>
MW_INLINE void solve_lanes(Body* body, WideRows& c, WideSums* p, int l0, const WideSoftness& sf) {
  Side<V> A, B;
  gather(body, c.a + l0, A);
  gather(body, c.b + l0, B);
  const V zero = splat<V>(0.0), one = splat<V>(1.0);
  const V nx = load<V>(c.nx + l0), ny = load<V>(c.ny + l0), s0 = load<V>(c.s0 + l0);
  const RowConstants<V> k = row_constants(A, B, s0);
  const V s = s0 + nx * (A.dpx - B.dpx) + ny * (A.dpy - B.dpy);
  const V vn = nx * (A.vx - B.vx) + ny * (A.vy - B.vy);
  // Normal: a speculative row (s > 0) closes the gap and no more; a penetrating one is soft
  // in the solve and rigid without bias in the relax.
  const auto speculative = s > zero;
  const V close = s * splat<V>(sf.inv_h);
  V bias, mass_scale = one, impulse_scale = zero;
  if (kBias) {
    bias = speculative ? close : vmax(splat<V>(sf.bias_rate) * s, splat<V>(-sf.push));
    mass_scale = speculative ? one : splat<V>(sf.mass_scale);
    impulse_scale = speculative ? zero : splat<V>(sf.impulse_scale);
  } else {
    bias = speculative ? close : zero;
  }
  V ln = load<V>(c.ln + l0);
  const V raw = -k.mn * mass_scale * (vn + bias) - impulse_scale * ln;
  const V next = vmax(ln + raw, zero);
  const V dn = next - ln;
  ln = next;
  A.vx += A.im * dn * nx;
  A.vy += A.im * dn * ny;
  B.vx -= B.im * dn * nx;
  B.vy -= B.im * dn * ny;
  // Friction along the tangent left_perp(n).
  const V tx = -ny, ty = nx;
  const V alpha = k.alpha, beta = k.beta;
  const V vt = tx * (A.vx - B.vx) + ty * (A.vy - B.vy) - alpha * A.w - beta * B.w;
  const V bound = load<V>(c.mu + l0) * ln;
  V lt = load<V>(c.lt + l0);
  const V lt_next = vclamp(lt - k.mt * vt, -bound, bound);
  const V dt = lt_next - lt;
  lt = lt_next;
  A.vx += A.im * dt * tx;
  A.vy += A.im * dt * ty;
  A.w -= A.ii * alpha * dt;
  B.vx -= B.im * dt * tx;
  B.vy -= B.im * dt * ty;
  B.w -= B.ii * beta * dt;
  // Rolling resistance, only where the row has a lever (as the serial row's branch).
  const V lever = load<V>(c.lever + l0);
  const auto rolls = lever > zero;
  const V rb = lever * ln;
  V lr = load<V>(c.lr + l0);
  const V lr_next = vclamp(lr - k.mr * (A.w - B.w), -rb, rb);
  const V dr = lr_next - lr;
  A.w = rolls ? A.w + A.ii * dr : A.w;
  B.w = rolls ? B.w - B.ii * dr : B.w;
  lr = rolls ? lr_next : lr;
  store(c.ln + l0, ln);
  store(c.lt + l0, lt);
  store(c.lr + l0, lr);
  if (!kBias) {
    store(p->pn + l0, load<V>(p->pn + l0) + ln);
    store(p->pt + l0, load<V>(p->pt + l0) + lt);
    store(p->pr + l0, load<V>(p->pr + l0) + lr);
  }
  scatter(body, c.a + l0, A);
  scatter(body, c.b + l0, B);
}

// The bodies of the chunk kAhead chunks on, asked for before they are needed: a colour's
// chunks reach their bodies in key order but with gaps no stride prefetcher follows, and at
// 30k disks and more the bodies no longer fit in one core's L2.
constexpr std::size_t kAhead = 4;
MW_INLINE void prefetch_bodies(const Body* body, const WideRows* rows, std::size_t k, std::size_t chunks) {
  if (k + kAhead >= chunks) return;
  const WideRows& c = rows[k + kAhead];
  for (int l = 0; l < kLanes; ++l) {
    __builtin_prefetch(body + c.a[l], 1);
    __builtin_prefetch(body + c.b[l], 1);
  }
}

// The three passes over all chunks, in order, for one lane width.
template <class V>
MW_INLINE void warm_start_all(Body* body, WideRows* rows, std::size_t chunks) {
  for (std::size_t k = 0; k < chunks; ++k) {
    prefetch_bodies(body, rows, k, chunks);
    for (int l0 = 0; l0 < kLanes; l0 += width<V>()) warm_start_lanes<V>(body, rows[k], l0);
  }
}
template <bool kBias, class V>
MW_INLINE void solve_all(Body* body, WideRows* rows, WideSums* sums, std::size_t chunks,
                         const WideSoftness& sf) {
  for (std::size_t k = 0; k < chunks; ++k) {
    prefetch_bodies(body, rows, k, chunks);
    for (int l0 = 0; l0 < kLanes; l0 += width<V>())
      solve_lanes<kBias, V>(body, rows[k], kBias ? nullptr : sums + k, l0, sf);
  }
}

struct Kernels {
  void (*warm_start)(Body*, WideRows*, std::size_t);
  void (*solve)(Body*, WideRows*, std::size_t, const WideSoftness&);
  void (*relax)(Body*, WideRows*, WideSums*, std::size_t, const WideSoftness&);
};

// The x86-64 baseline: two lanes per SSE2 register (a generic four-lane vector would be
// split by the compiler into scalar shuffles through the stack).
void warm_start_sse2(Body* body, WideRows* rows, std::size_t n) { warm_start_all<f64x2>(body, rows, n); }
void solve_sse2(Body* body, WideRows* rows, std::size_t n, const WideSoftness& sf) {
  solve_all<true, f64x2>(body, rows, nullptr, n, sf);
}
void relax_sse2(Body* body, WideRows* rows, WideSums* sums, std::size_t n, const WideSoftness& sf) {
  solve_all<false, f64x2>(body, rows, sums, n, sf);
}

#if defined(MILLWEAR_HAVE_AVX2_TARGET)
// AVX2 (with AVX's four-double registers; no FMA: -ffp-contract=off and no "fma" target).
#define MW_AVX2 __attribute__((target("avx2")))
MW_AVX2 void warm_start_avx2(Body* body, WideRows* rows, std::size_t n) { warm_start_all<f64x4>(body, rows, n); }
MW_AVX2 void solve_avx2(Body* body, WideRows* rows, std::size_t n, const WideSoftness& sf) {
  solve_all<true, f64x4>(body, rows, nullptr, n, sf);
}
MW_AVX2 void relax_avx2(Body* body, WideRows* rows, WideSums* sums, std::size_t n, const WideSoftness& sf) {
  solve_all<false, f64x4>(body, rows, sums, n, sf);
}
#endif

const Kernels kBaseline{warm_start_sse2, solve_sse2, relax_sse2};
std::atomic<bool> force_baseline{false};

const Kernels& kernels() {
  static const Kernels k = [] {
#if defined(MILLWEAR_HAVE_AVX2_TARGET)
    if (__builtin_cpu_supports("avx2")) return Kernels{warm_start_avx2, solve_avx2, relax_avx2};
#endif
    return kBaseline;
  }();
  return force_baseline.load(std::memory_order_relaxed) ? kBaseline : k;
}

}  // namespace

int lane_width() { return kernels().warm_start == kBaseline.warm_start ? 2 : 4; }
void force_baseline_lanes(bool on) { force_baseline.store(on, std::memory_order_relaxed); }

void wide_warm_start(Body* body, WideRows* rows, std::size_t chunks) { kernels().warm_start(body, rows, chunks); }

void wide_solve(Body* body, WideRows* rows, std::size_t chunks, const WideSoftness& soft) {
  kernels().solve(body, rows, chunks, soft);
}

void wide_relax(Body* body, WideRows* rows, WideSums* sums, std::size_t chunks, double inv_h) {
  WideSoftness soft;
  soft.inv_h = inv_h;
  kernels().relax(body, rows, sums, chunks, soft);
}

void ColouredRows::begin(int bodies, std::size_t contacts) {
  dummy_ = bodies;
  mask_.assign(static_cast<std::size_t>(bodies) + 1, 0u);
  if (added_.size() < contacts) added_.resize(contacts);
  added_n_ = 0;
  std::fill(std::begin(count_), std::end(count_), 0);
}

void ColouredRows::layout() {
  // Each colour starts on a chunk boundary: a chunk never mixes colours.
  std::size_t* first = first_;
  std::size_t chunk = 0;
  colours_ = 0;
  for (int c = 0; c < kMaxColours; ++c) {
    first[c] = chunk;
    chunk += (static_cast<std::size_t>(count_[c]) + kLanes - 1) / kLanes;
    if (count_[c] > 0) colours_ = c + 1;
  }
  first[kMaxColours] = chunk;
  chunks_ = chunk;
  if (wide_.size() < chunks_) {
    wide_.resize(chunks_);
    sums_.resize(chunks_);
  }
  // Contacts in the order added within each colour.
  std::size_t next[kMaxColours];
  for (int c = 0; c < kMaxColours; ++c) next[c] = first[c] * kLanes;
  for (std::size_t t = 0; t < added_n_; ++t) added_[t].slot = next[added_[t].colour]++;
  // Padding: an inert row between two dummy bodies (apart, not closing: zero impulses).
  for (int c = 0; c < kMaxColours; ++c) {
    for (std::size_t s = next[c]; s < first[c + 1] * kLanes; ++s) {
      WideRows& w = wide_[s / kLanes];
      const std::size_t l = s % kLanes;
      w.a[l] = w.b[l] = dummy_;
      w.nx[l] = w.ny[l] = 0.0;
      w.s0[l] = 1.0;
      w.mu[l] = w.lever[l] = 0.0;
      w.ln[l] = w.lt[l] = w.lr[l] = 0.0;
      WideSums& p = sums_[s / kLanes];
      p.pn[l] = p.pt[l] = p.pr[l] = 0.0;
    }
  }
}

}  // namespace millwear::soft
