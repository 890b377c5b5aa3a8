#include "engine/soft/narrow_phase.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#if defined(MILLWEAR_HAVE_AVX2_TARGET)
#include <immintrin.h>
#endif

#include "engine/soft/colour_solve.hpp"
#include "geometry/vec2.hpp"

namespace millwear::soft {

namespace {

// The liner lookup is built for this many times the reach asked of it, so that a charge
// speeding up does not rebuild it step after step.
constexpr double kLinerReachHeadroom = 1.5;
// Of a disk at rest: its radius plus the margins of two disks at rest.
constexpr double kRestMargins = 2.0;

// The gap of a new disk-pair contact (all that the skip test of the passes reads).
void add_pair_contact(const Disks& disks, PairSet& pairs, std::size_t q, int i, int j) {
  const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(j);
  PairGap& g = pairs.gap[q];
  ContactKey& key = pairs.key[q];
  g.a = i;
  g.b = j;
  pairs.state[q] = 0;
  key.key = pair_key(i, j);
  key.event_J = 0.0;
  const double dx = disks.x[a] - disks.x[b], dy = disks.y[a] - disks.y[b];
  const double dist = std::sqrt(dx * dx + dy * dy);
  if (dist > 0.0) {
    g.nx = dx / dist;
    g.ny = dy / dist;
  } else {
    g.nx = 0.0;
    g.ny = 1.0;
  }
  g.s0 = dist - disks.radius[a] - disks.radius[b];
}

using Candidate = PairSearch::Candidate;

// The pair scan of one run of candidates [k0, k1) (contiguous in grid order) against p:
// each key stored at out[found], counted only where the two are within reach (no branch:
// whether a neighbour is a pair follows no pattern a predictor can learn). Room for
// k1 - k0 + kScanSlack keys past found is the caller's to make.
constexpr int kScanSlack = 3;
inline std::size_t scan_run(const Candidate& p, const Candidate* cd, int k0, int k1,
                            std::uint64_t* out, std::size_t found) {
  for (int k = k0; k < k1; ++k) {
    const Candidate& q = cd[k];
    const double dx = p.x - q.x, dy = p.y - q.y;
    // (r_p + margin_p) + (r_q + margin_q): a sum of two terms is the same whichever disk
    // scans, so the pair set does not depend on the grid.
    const double reach = p.reach + q.reach;
    // The lower index by masks: the compiler turns a select of two indices into a branch,
    // and which disk comes first follows no pattern either.
    const auto pj = static_cast<std::uint64_t>(p.j), qj = static_cast<std::uint64_t>(q.j);
    const std::uint64_t p_low = 0 - static_cast<std::uint64_t>(pj < qj);
    const std::uint64_t lo = qj ^ ((pj ^ qj) & p_low);
    out[found] = (lo << 32) | (pj ^ qj ^ lo);
    found += dx * dx + dy * dy < reach * reach ? 1 : 0;
  }
  return found;
}

#if defined(MILLWEAR_HAVE_AVX2_TARGET)
#define MW_AVX2 __attribute__((target("avx2")))
// The same scan four candidates at a time: the same operations on each (no contraction), so
// the same pairs. A group reads up to three candidates past k1 (the candidate array has that
// many spare at its end); their lanes are masked off. The keys of a group's pairs are packed
// to its front by a permutation chosen by the group's 4-bit mask.
struct PackTable {
  alignas(32) std::int32_t index[16][8] = {};
  constexpr PackTable() {
    for (int m = 0; m < 16; ++m) {
      int n = 0;
      for (int l = 0; l < 4; ++l)
        if (m & (1 << l)) {
          index[m][2 * n] = 2 * l;
          index[m][2 * n + 1] = 2 * l + 1;
          ++n;
        }
      for (; n < 4; ++n) index[m][2 * n] = index[m][2 * n + 1] = 0;
    }
  }
};
constexpr PackTable kPack;

MW_AVX2 inline std::size_t scan_run_avx2(const Candidate& p, const Candidate* cd, int k0, int k1,
                                         std::uint64_t* out, std::size_t found) {
  static_assert(sizeof(Candidate) == 32 && offsetof(Candidate, x) == 0 && offsetof(Candidate, j) == 24,
                "a candidate is loaded as four doubles' worth: x, y, reach, then j");
  const __m256d px = _mm256_set1_pd(p.x), py = _mm256_set1_pd(p.y), pr = _mm256_set1_pd(p.reach);
  const __m256i pj = _mm256_set1_epi64x(p.j);
  const __m256i low32 = _mm256_set1_epi64x(0xffffffff);
  const __m256i lane = _mm256_setr_epi64x(0, 1, 2, 3);
  for (int k = k0; k < k1; k += 4) {
    // Four candidates in, their columns out.
    const __m256d c0 = _mm256_loadu_pd(&cd[k].x), c1 = _mm256_loadu_pd(&cd[k + 1].x);
    const __m256d c2 = _mm256_loadu_pd(&cd[k + 2].x), c3 = _mm256_loadu_pd(&cd[k + 3].x);
    const __m256d t0 = _mm256_unpacklo_pd(c0, c1), t1 = _mm256_unpackhi_pd(c0, c1);
    const __m256d t2 = _mm256_unpacklo_pd(c2, c3), t3 = _mm256_unpackhi_pd(c2, c3);
    const __m256d qx = _mm256_permute2f128_pd(t0, t2, 0x20), qy = _mm256_permute2f128_pd(t1, t3, 0x20);
    const __m256d qr = _mm256_permute2f128_pd(t0, t2, 0x31), qjd = _mm256_permute2f128_pd(t1, t3, 0x31);
    const __m256d dx = _mm256_sub_pd(px, qx), dy = _mm256_sub_pd(py, qy);
    const __m256d reach = _mm256_add_pd(pr, qr);
    const __m256d d2 = _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy));
    const __m256d within = _mm256_cmp_pd(d2, _mm256_mul_pd(reach, reach), _CMP_LT_OQ);
    const __m256i in_run = _mm256_cmpgt_epi64(_mm256_set1_epi64x(k1 - k), lane);
    const int mask = _mm256_movemask_pd(_mm256_and_pd(within, _mm256_castsi256_pd(in_run)));
    const __m256i qj = _mm256_and_si256(_mm256_castpd_si256(qjd), low32);
    const __m256i p_low = _mm256_cmpgt_epi64(qj, pj);
    const __m256i lo = _mm256_blendv_epi8(qj, pj, p_low), hi = _mm256_blendv_epi8(pj, qj, p_low);
    const __m256i key = _mm256_or_si256(_mm256_slli_epi64(lo, 32), hi);
    const __m256i order = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPack.index[mask]));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + found), _mm256_permutevar8x32_epi32(key, order));
    found += static_cast<std::size_t>(__builtin_popcount(static_cast<unsigned>(mask)));
  }
  return found;
}
#endif

// One range of the scan [k_begin, k_end): each candidate p against the cells after its own
// within its reach plus the largest reach; the count of keys found. kWide: four candidates
// at a time.
template <bool kWide>
__attribute__((always_inline)) inline std::size_t scan_range(const Grid& grid, const Candidate* cd, int k_begin,
                                                             int k_end, double reach_max,
                                                             std::vector<std::uint64_t>& keys) {
  const int nx = grid.nx;
  const int* start = grid.start.data();
  std::size_t found = 0;
  auto scan = [&](const Candidate& p, int k0, int k1) {
    const std::size_t need = found + static_cast<std::size_t>(k1 - k0 + kScanSlack);
    if (keys.size() < need) keys.resize(2 * need);
#if defined(MILLWEAR_HAVE_AVX2_TARGET)
    if constexpr (kWide) {
      found = scan_run_avx2(p, cd, k0, k1, keys.data(), found);
      return;
    }
#endif
    found = scan_run(p, cd, k0, k1, keys.data(), found);
  };
  for (int k = k_begin; k < k_end; ++k) {
    const Candidate& p = cd[k];
    const double box = p.reach + reach_max;
    const int x_lo = grid.col(p.x - box), x_hi = grid.col(p.x + box);
    const int row = grid.row(p.y);
    // The rest of this row: the disks after p in its own cell, then the cells to its right.
    scan(p, k + 1, start[row * nx + x_hi + 1]);
    for (int gy = row + 1, y_hi = grid.row(p.y + box); gy <= y_hi; ++gy)
      scan(p, start[gy * nx + x_lo], start[gy * nx + x_hi + 1]);
  }
  return found;
}

std::size_t scan_range_baseline(const Grid& grid, const Candidate* cd, int k_begin, int k_end,
                                double reach_max, std::vector<std::uint64_t>& keys) {
  return scan_range<false>(grid, cd, k_begin, k_end, reach_max, keys);
}
#if defined(MILLWEAR_HAVE_AVX2_TARGET)
MW_AVX2 std::size_t scan_range_avx2(const Grid& grid, const Candidate* cd, int k_begin, int k_end,
                                    double reach_max, std::vector<std::uint64_t>& keys) {
  return scan_range<true>(grid, cd, k_begin, k_end, reach_max, keys);
}
#endif

// Below this many disks the serial bucketing is as fast as handing out its four stages.
constexpr int kThreadedBucketDisks = 4096;
constexpr std::size_t kBucketDisksPerRange = 4096;

// The found pairs' upper indices bucketed by their lower index a (counting sort): those of
// a at upper[bucket_end[a - 1] .. bucket_end[a]) (from 0 for a = 0), in no particular
// order (find_pairs sorts each bucket). Returns the count of pairs. With threads, by
// blocks of the scan's ranges, one per thread: block b puts its pairs of each a after
// those of the blocks before it. Either way a bucket holds the same pairs.
std::size_t bucket_by_lower(PairSearch& search, int ranges, int disks, Workers& workers) {
  const auto n = static_cast<std::size_t>(disks);
  std::vector<int>& bucket = search.bucket_end;
  const int blocks = std::min(workers.threads(), ranges);
  if (blocks <= 1 || disks < kThreadedBucketDisks) {
    bucket.assign(n + 1, 0);
    std::size_t total = 0;
    for (int rg = 0; rg < ranges; ++rg) {
      const std::uint64_t* keys = search.found_keys[static_cast<std::size_t>(rg)].data();
      const std::size_t found = search.found[static_cast<std::size_t>(rg)];
      for (std::size_t t = 0; t < found; ++t) bucket[(keys[t] >> 32) + 1] += 1;
      total += found;
    }
    for (std::size_t i = 0; i < n; ++i) bucket[i + 1] += bucket[i];
    if (search.upper.size() < total) search.upper.resize(2 * total);
    for (int rg = 0; rg < ranges; ++rg) {
      const std::uint64_t* keys = search.found_keys[static_cast<std::size_t>(rg)].data();
      const std::size_t found = search.found[static_cast<std::size_t>(rg)];
      for (std::size_t t = 0; t < found; ++t) {
        const std::uint64_t key = keys[t];
        const auto slot = static_cast<std::size_t>(bucket[key >> 32]++);
        search.upper[slot] = static_cast<int>(key & 0xffffffffu);
      }
    }
    return total;
  }
  bucket.resize(n + 1);
  search.counts.resize(static_cast<std::size_t>(blocks) * n);
  const int disk_ranges = range_count(n, kBucketDisksPerRange);
  search.range_pairs.resize(static_cast<std::size_t>(disk_ranges));
  const auto block_begin = [&](int b) { return static_cast<int>(static_cast<std::int64_t>(ranges) * b / blocks); };
  // The count of each disk's pairs in each block.
  workers.run(blocks, [&](int b) {
    int* count = search.counts.data() + static_cast<std::size_t>(b) * n;
    std::fill(count, count + n, 0);
    for (int rg = block_begin(b); rg < block_begin(b + 1); ++rg) {
      const std::uint64_t* keys = search.found_keys[static_cast<std::size_t>(rg)].data();
      const std::size_t found = search.found[static_cast<std::size_t>(rg)];
      for (std::size_t t = 0; t < found; ++t) count[keys[t] >> 32] += 1;
    }
  });
  // Per disk, the blocks' offsets within its bucket (the counts become them); bucket[a]
  // holds the bucket's size for now, range_pairs each range's.
  workers.run(disk_ranges, [&](int r) {
    const std::size_t a0 = static_cast<std::size_t>(r) * kBucketDisksPerRange, a1 = std::min(n, a0 + kBucketDisksPerRange);
    int in_range = 0;
    for (std::size_t a = a0; a < a1; ++a) {
      int in_bucket = 0;
      for (int b = 0; b < blocks; ++b) {
        int& k = search.counts[static_cast<std::size_t>(b) * n + a];
        const int t = k;
        k = in_bucket;
        in_bucket += t;
      }
      bucket[a] = in_bucket;
      in_range += in_bucket;
    }
    search.range_pairs[static_cast<std::size_t>(r)] = in_range;
  });
  std::size_t total = 0;
  for (int& k : search.range_pairs) {
    const int t = k;
    k = static_cast<int>(total);
    total += static_cast<std::size_t>(t);
  }
  if (search.upper.size() < total) search.upper.resize(2 * total);
  // Each bucket's end, and each block's cursor in it.
  workers.run(disk_ranges, [&](int r) {
    const std::size_t a0 = static_cast<std::size_t>(r) * kBucketDisksPerRange, a1 = std::min(n, a0 + kBucketDisksPerRange);
    int first = search.range_pairs[static_cast<std::size_t>(r)];
    for (std::size_t a = a0; a < a1; ++a) {
      for (int b = 0; b < blocks; ++b) search.counts[static_cast<std::size_t>(b) * n + a] += first;
      first += bucket[a];
      bucket[a] = first;
    }
  });
  bucket[n] = static_cast<int>(total);
  // The scatter, each block into its own slots.
  workers.run(blocks, [&](int b) {
    int* cursor = search.counts.data() + static_cast<std::size_t>(b) * n;
    int* upper = search.upper.data();
    for (int rg = block_begin(b); rg < block_begin(b + 1); ++rg) {
      const std::uint64_t* keys = search.found_keys[static_cast<std::size_t>(rg)].data();
      const std::size_t found = search.found[static_cast<std::size_t>(rg)];
      for (std::size_t t = 0; t < found; ++t)
        upper[cursor[keys[t] >> 32]++] = static_cast<int>(keys[t] & 0xffffffffu);
    }
  });
  return total;
}

}  // namespace

void build_liner_search(const Model& model, const LinerModel& liner, LinerSearch& search) {
  const double rest_reach =
      kLinerReachHeadroom * (model.r_max_m + kRestMargins * model.margin_base_m);
  search.lookup.build(liner.mill, std::max(search.reach_needed_m, rest_reach));
}

void fit_liner_search(const Model& model, const LinerModel& liner, const StepBounds& bounds,
                      double mill_speed_rad_s, LinerSearch& search) {
  const double reach = model.r_max_m + bounds.margin_max_m +
                       std::fabs(mill_speed_rad_s) * liner.max_r_m * model.dt_s;
  if (reach <= search.lookup.reach_m()) return;
  search.reach_needed_m = kLinerReachHeadroom * reach;
  search.lookup.build(liner.mill, search.reach_needed_m);
}

// Each pair is found once: a disk scans only the cells after its own in grid order (the
// rest of its own cell and row, the rows above) within its reach plus the largest reach,
// which holds every partner it can have. The pairs are then bucketed by their lower index
// and each bucket sorted, so the list comes out in key order.
void find_pairs(const Model& model, const Disks& disks, const Grid& grid,
                const StepBounds& bounds, PairSearch& search, PairSet& pairs,
                Workers& workers) {
  constexpr std::size_t kPerRange = 1024;  // candidates (disks) per range of the scan
  pairs.clear();
  const double* x = disks.x.data();
  const double* y = disks.y.data();
  const double* r = disks.radius.data();
  const double* margin = disks.margin.data();
  const int placed = grid.placed();
  // kScanSlack spare candidates at the end, read (and masked off) by the four-wide scan.
  search.candidates.resize(static_cast<std::size_t>(placed) + kScanSlack);
  const int ranges = range_count(static_cast<std::size_t>(placed), kPerRange);
  if (search.found_keys.size() < static_cast<std::size_t>(ranges)) {
    search.found_keys.resize(static_cast<std::size_t>(ranges));
    search.found.resize(static_cast<std::size_t>(ranges));
  }
  workers.run(ranges, [&](int rg) {
    const std::size_t k0 = static_cast<std::size_t>(rg) * kPerRange;
    const std::size_t k1 = std::min(static_cast<std::size_t>(placed), k0 + kPerRange);
    for (std::size_t k = k0; k < k1; ++k) {
      const int j = grid.order[k];
      search.candidates[k] = {x[j], y[j], r[j] + margin[j], j};
    }
  });
  const Candidate* cd = search.candidates.data();
  // Any partner's reach is at most this; the slack (far above rounding) keeps a pair at
  // the edge of the box from being lost to the rounding of the box.
  const double reach_max = model.r_max_m + bounds.margin_max_m + 1e-6 * model.r_min_m;
  // The four-wide scan where the coloured lanes are four wide (colour_solve.hpp: AVX2, and
  // not forced to the baseline); both find the same pairs.
  auto* scan_range_fn = &scan_range_baseline;
#if defined(MILLWEAR_HAVE_AVX2_TARGET)
  if (lane_width() == 4) scan_range_fn = &scan_range_avx2;
#endif
  workers.run(ranges, [&](int rg) {
    const int k_end = static_cast<int>(std::min(static_cast<std::size_t>(placed),
                                                (static_cast<std::size_t>(rg) + 1) * kPerRange));
    search.found[static_cast<std::size_t>(rg)] =
        scan_range_fn(grid, cd, rg * static_cast<int>(kPerRange), k_end, reach_max,
                      search.found_keys[static_cast<std::size_t>(rg)]);
  });
  // Bucket by the lower index (counting sort), then sort each bucket by the upper one.
  const std::size_t total = bucket_by_lower(search, ranges, disks.n, workers);
  // bucket[i] is now the end of bucket i, and the start of bucket i + 1; a pair's slot is
  // its index in the key-ordered list.
  std::vector<int>& bucket = search.bucket_end;
  pairs.resize(total);
  int* upper = search.upper.data();
  // By disk, in the disk stages' ranges: the work per disk varies with its pair count, and
  // small ranges even it out between the threads.
  workers.run_disks(disks.n, [&](int i0, int i1) {
    int b0 = i0 == 0 ? 0 : bucket[static_cast<std::size_t>(i0) - 1];
    for (int i = i0; i < i1; ++i) {
      const int b1 = bucket[static_cast<std::size_t>(i)];
      // A handful per disk: insertion sort.
      for (int p = b0 + 1; p < b1; ++p)
        for (int q = p; q > b0 && upper[q - 1] > upper[q]; --q) std::swap(upper[q - 1], upper[q]);
      for (int p = b0; p < b1; ++p)
        add_pair_contact(disks, pairs, static_cast<std::size_t>(p), i, upper[p]);
      b0 = b1;
    }
  });
}

void find_liner_contacts(const Model& model, const LinerModel& liner, LinerSearch& search,
                         const Disks& disks, double mill_angle_rad, double mill_speed_rad_s,
                         LinerSet& contacts, Workers& workers) {
  constexpr std::size_t kPerRange = 1024;  // disks per range
  const double omega = mill_speed_rad_s;
  const double cs = std::cos(mill_angle_rad), sn = std::sin(mill_angle_rad);
  const double liner_travel = std::fabs(omega) * liner.max_r_m * model.dt_s;
  const Materials& mat = model.materials;
  const auto n = static_cast<std::size_t>(disks.n);
  const int ranges = range_count(n, kPerRange);
  if (search.found.size() < static_cast<std::size_t>(ranges)) {
    search.found.resize(static_cast<std::size_t>(ranges));
    search.count.resize(static_cast<std::size_t>(ranges));
    search.offset.resize(static_cast<std::size_t>(ranges));
    search.hits.resize(static_cast<std::size_t>(ranges));
  }
  const auto max_hits = static_cast<std::size_t>(search.lookup.max_hits());
  for (int r = 0; r < ranges; ++r) {
    std::vector<LinerHit>& hits = search.hits[static_cast<std::size_t>(r)];
    if (hits.size() < max_hits) hits.resize(max_hits);  // grows with the bins, rarely
  }
  // The hits of each range of disks.
  workers.run(ranges, [&](int r) {
    std::vector<LinerSearch::Found>& found = search.found[static_cast<std::size_t>(r)];
    std::size_t count = 0;
    LinerHit* hits = search.hits[static_cast<std::size_t>(r)].data();
    const std::size_t k0 = static_cast<std::size_t>(r) * kPerRange, k1 = std::min(n, k0 + kPerRange);
    for (std::size_t k = k0; k < k1; ++k) {
      if (!disks.active[k]) continue;
      const double margin = disks.margin[k] + liner_travel;
      const double rad = disks.radius[k];
      const double x = disks.x[k], y = disks.y[k];
      // Into the mill frame (rotate by -theta).
      const Vec2 pm{cs * x + sn * y, -sn * x + cs * y};
      if (!search.lookup.may_touch(pm, rad + margin)) continue;
      const int hit_n = search.lookup.query(pm, rad, margin, hits);
      if (found.size() < count + static_cast<std::size_t>(hit_n)) found.resize(2 * (count + static_cast<std::size_t>(hit_n)));
      for (int h = 0; h < hit_n; ++h) found[count++] = {static_cast<int>(k), hits[h]};
    }
    search.count[static_cast<std::size_t>(r)] = count;
  });
  std::size_t total = 0;
  for (int r = 0; r < ranges; ++r) {
    search.offset[static_cast<std::size_t>(r)] = total;
    total += search.count[static_cast<std::size_t>(r)];
  }
  contacts.resize(total);
  // The contacts, in disk order (each range at its offset).
  workers.run(ranges, [&](int r) {
    const LinerSearch::Found* found = search.found[static_cast<std::size_t>(r)].data();
    const std::size_t count = search.count[static_cast<std::size_t>(r)];
    std::size_t q = search.offset[static_cast<std::size_t>(r)];
    for (std::size_t t = 0; t < count; ++t, ++q) {
      const int i = found[t].disk;
      const LinerHit& hit = found[t].hit;
      const auto k = static_cast<std::size_t>(i);
      const double rad = disks.radius[k];
      const double x = disks.x[k], y = disks.y[k];
      const Body& A = disks.body[k];
      const std::uint8_t sp = disks.species[k];
      LinerGap& g = contacts.gap[q];
      LinerRow& c = contacts.row[q];
      LinerInfo& info = contacts.info[q];
      g.a = i;
      contacts.impulse[q] = Impulse{};
      contacts.state[q] = kBuilt;
      contacts.sum[q] = StepSum{};
      contacts.key[q] = {pair_key(i, hit.owner), 0.0};
      info.edge = hit.edge;
      info.owner = hit.owner;
      g.nx = cs * hit.normal.x - sn * hit.normal.y;  // back to the world frame
      g.ny = sn * hit.normal.x + cs * hit.normal.y;
      g.s0 = hit.gap;
      c.alpha = rad + 0.5 * g.s0;
      info.px = x - c.alpha * g.nx;
      info.py = y - c.alpha * g.ny;
      g.vlx = -omega * info.py;
      g.vly = omega * info.px;
      c.mn = A.im > 0.0 ? 1.0 / A.im : 0.0;
      const double it = A.im + A.ii * c.alpha * c.alpha;
      c.mt = it > 0.0 ? 1.0 / it : 0.0;
      c.mr = A.ii > 0.0 ? 1.0 / A.ii : 0.0;
      c.mu = mat.liner_friction[sp];
      info.e = mat.liner_restitution[sp];
      c.lever = mat.rolling[sp] * rad;
      info.vn0 = (A.vx - g.vlx) * g.nx + (A.vy - g.vly) * g.ny;
    }
  });
}

void match_warm_start(Contacts& contacts, Accounting& accounting, MatchScratch& scratch,
                      Workers& workers) {
  constexpr std::size_t kPerRange = 2048;
  const bool spectrum = accounting.options.collision_spectrum;
  auto merge = [&](auto& now, const auto& old, bool events) {
    const std::size_t m = old.size(), count = now.size();
    const int ranges = std::max(1, range_count(count, kPerRange));
    if (scratch.ended.size() < static_cast<std::size_t>(ranges)) {
      scratch.ended.resize(static_cast<std::size_t>(ranges));
      scratch.count.resize(static_cast<std::size_t>(ranges));
    }
    // Where this step's key k falls in last step's list (the first old key not below it).
    auto old_from = [&](std::size_t q) -> std::size_t {
      if (q >= count) return m;
      const std::uint64_t k = now.key[q].key;
      std::size_t lo = 0, hi = m;
      while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if (old.key[mid].key < k) lo = mid + 1; else hi = mid;
      }
      return lo;
    };
    workers.run(ranges, [&](int r) {
      const std::size_t q0 = static_cast<std::size_t>(r) * kPerRange;
      const std::size_t q1 = std::min(count, q0 + kPerRange);
      // The first range also takes the old keys below this step's first; the last, those
      // above its last.
      std::size_t p = r == 0 ? 0 : old_from(q0);
      const std::size_t p_end = r == ranges - 1 ? m : old_from(q1);
      std::vector<CollisionEvent>& ended = scratch.ended[static_cast<std::size_t>(r)];
      std::size_t ended_n = 0;
      auto end_event = [&](double energy_J) {
        if (ended_n == ended.size()) ended.resize(2 * ended_n + 16);
        ended[ended_n++] = collision_event(energy_J);
      };
      for (std::size_t q = q0; q < q1; ++q) {
        ContactKey& c = now.key[q];
        while (p < p_end && old.key[p].key < c.key) {
          if (events && old.key[p].event_J > 0.0) end_event(old.key[p].event_J);
          ++p;
        }
        if (p < p_end && old.key[p].key == c.key) {
          // Only a live row carries impulses; a row that is not live stores none (its
          // slot holds whatever it held, read by nobody), so the slot is copied either way:
          // a third of the rows are live, in no pattern a branch predictor learns.
          now.impulse[q] = old.impulse[p];
          now.state[q] |= old.state[p] & kLive;
          if (events) c.event_J = old.key[p].event_J;  // otherwise zero in both
          ++p;
        }
      }
      for (; p < p_end; ++p)
        if (events && old.key[p].event_J > 0.0) end_event(old.key[p].event_J);
      scratch.count[static_cast<std::size_t>(r)] = ended_n;
    });
    for (int r = 0; r < ranges; ++r)
      for (std::size_t e = 0; e < scratch.count[static_cast<std::size_t>(r)]; ++e)
        account_collision_event(accounting, scratch.ended[static_cast<std::size_t>(r)][e]);
  };
  merge(contacts.pairs, contacts.pairs_old, spectrum);
  merge(contacts.liner, contacts.liner_old, false);
}

}  // namespace millwear::soft
