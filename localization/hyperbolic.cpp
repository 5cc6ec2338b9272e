#include "localization/hyperbolic.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>
#include <tuple>
#include <vector>

#include "localization/finish.h"
#include "localization/joint_fit.h"
#include "localization/range_cost.h"

namespace rfidray::loc {

std::vector<Hyperbola> build_conics(const PreparedTag& prep, const LocalizeOptions& options, double* stride_used) {
  double path_length = 0.0;
  for (const RangeSegment& s : prep.segments)
    for (size_t k = 1; k < s.antenna_m.size(); ++k) path_length += (s.antenna_m[k] - s.antenna_m[k - 1]).norm();
  const double stride = std::max(options.stride_m, path_length / std::max(1, options.max_conics));
  if (stride_used) *stride_used = stride;
  std::vector<Hyperbola> conics;
  for (const RangeSegment& s : prep.segments) {
    const Vec3& ref = s.antenna_m[0];
    Vec3 last = ref;
    for (size_t k = 1; k < s.antenna_m.size(); ++k) {
      if ((s.antenna_m[k] - last).norm() < stride) continue;
      last = s.antenna_m[k];
      Hyperbola h{ref, s.antenna_m[k], s.range_m[k] - s.range_m[0], s.range_m[k]};
      if (h.valid()) conics.push_back(h);
    }
  }
  return conics;
}

std::vector<Intersection> intersect_conics(const std::vector<Hyperbola>& conics, const LocalizeOptions& options,
                                           double plane_height_m) {
  constexpr int kRays = 720;
  std::vector<Intersection> out;
  const int n = static_cast<int>(conics.size());
  // Kept per thread from tag to tag: ~60 sections of ~35 kB each, which freed and allocated again per tag
  // cost page faults (glibc returns the freed top of the heap to the system).
  thread_local std::vector<PlaneSection> sections;
  if (static_cast<int>(sections.size()) < n) sections.resize(n);
  for (int i = 0; i < n; ++i) sample_section(conics[i], plane_height_m, kRays, options.max_range_m, sections[i]);
  thread_local std::vector<Vec3> crossings;
  for (int b = 1; b < n; ++b) {     // the new conic
    for (int a = 0; a < b; ++a) {   // every previous one
      intersect_in_plane(conics[b], sections[b], conics[a], crossings);
      for (const Vec3& p2 : crossings) {
        Vec3 p = p2;
        Vec3 grads[3] = {gradient(conics[a], p), gradient(conics[b], p), Vec3::Zero()};
        int gradient_count = 2;
        if (!options.height_known) {
          // 3-D: add a third conic from 8 evenly spread earlier anchors, the one with the best geometry.
          int best_c = -1;
          double best_q = 0.0;
          for (int t = 0; t < 8 && b > 2; ++t) {
            const int c = (t * (b - 1)) / 7;
            if (c == a || c == b) continue;
            const Vec3 g3[3] = {grads[0], grads[1], gradient(conics[c], p)};
            const double q = intersection_quality(g3, 3, false);
            if (q > best_q) best_q = q, best_c = c;
          }
          if (best_c < 0) continue;
          Vec3 x;
          if (!intersect_3d(conics[a], conics[b], conics[best_c], p, x)) continue;
          p = x;
          grads[0] = gradient(conics[a], p), grads[1] = gradient(conics[b], p), grads[2] = gradient(conics[best_c], p);
          gradient_count = 3;
        }
        if ((p - conics[a].f2).norm() > options.max_range_m || (p - conics[b].f2).norm() > options.max_range_m)
          continue;
        const double q = intersection_quality(grads, gradient_count, options.height_known);
        if (q <= 0.0) continue;
        out.push_back(Intersection{p, q, conics[b].phase_distance_m, a, b});
      }
    }
  }
  return out;
}

namespace {

using Key = std::tuple<long, long, long>;

// The intersections binned in cubic cells of side `cell`: each cell's points stored contiguously (x, y, z,
// quality arrays; within a cell in their order in the set), cells found through an open-addressing table
// (linear probing, load ≤ 1/2). The mode search looks up up to 7 × 7 cells per step, most of them empty: a
// probe here is one multiply and a compare, where std::unordered_map divided by a prime and followed a list.
class CellIndex {
 public:
  CellIndex(const std::vector<Intersection>& set, double cell) : cell_(cell) {
    size_t capacity = 16;
    while (capacity < 2 * set.size()) capacity *= 2;
    slot_.assign(capacity, -1);
    mask_ = capacity - 1;
    std::vector<int> cell_of(set.size());
    std::vector<int> count;
    for (size_t i = 0; i < set.size(); ++i) {
      const Key k = key(set[i].point);
      size_t s = hash(k) & mask_;
      while (slot_[s] >= 0 && keys_[slot_[s]] != k) s = (s + 1) & mask_;
      if (slot_[s] < 0) {
        slot_[s] = static_cast<int>(keys_.size());
        keys_.push_back(k);
        count.push_back(0);
      }
      cell_of[i] = slot_[s];
      ++count[slot_[s]];
    }
    start_.assign(keys_.size() + 1, 0);
    for (size_t c = 0; c < keys_.size(); ++c) start_[c + 1] = start_[c] + count[c];
    std::vector<int> next(start_.begin(), start_.end() - 1);
    x_.resize(set.size()), y_.resize(set.size()), z_.resize(set.size()), q_.resize(set.size());
    for (size_t i = 0; i < set.size(); ++i) {
      const int at = next[cell_of[i]]++;
      x_[at] = set[i].point.x(), y_[at] = set[i].point.y(), z_[at] = set[i].point.z(), q_[at] = set[i].quality;
    }
  }

  double cell() const { return cell_; }
  Key key(const Vec3& p) const {
    return Key{static_cast<long>(std::floor(p.x() / cell_)), static_cast<long>(std::floor(p.y() / cell_)),
               static_cast<long>(std::floor(p.z() / cell_))};
  }
  // The cell with key k, or −1 when no point lies in it.
  int find(const Key& k) const {
    for (size_t s = hash(k) & mask_;; s = (s + 1) & mask_) {
      const int c = slot_[s];
      if (c < 0 || keys_[c] == k) return c;
    }
  }
  int cells() const { return static_cast<int>(keys_.size()); }
  int points() const { return start_.empty() ? 0 : start_.back(); }
  const Key& cell_key(int c) const { return keys_[c]; }
  // Cell c's points: positions [begin(c), end(c)) of the arrays below.
  int begin(int c) const { return start_[c]; }
  int end(int c) const { return start_[c + 1]; }
  double x(int k) const { return x_[k]; }
  double y(int k) const { return y_[k]; }
  double z(int k) const { return z_[k]; }
  double quality(int k) const { return q_[k]; }
  // How many cells the occupied cells span in z (0 when the set is planar: no z neighbours to visit).
  long z_span() const {
    if (keys_.empty()) return 0;
    long lo = std::get<2>(keys_.front()), hi = lo;
    for (const Key& k : keys_) lo = std::min(lo, std::get<2>(k)), hi = std::max(hi, std::get<2>(k));
    return hi - lo;
  }

 private:
  static size_t hash(const Key& k) {
    // Large odd multipliers (as in spatial hashing, Teschner et al. 2003), mixed once more.
    const uint64_t h = static_cast<uint64_t>(std::get<0>(k)) * 73856093u ^ static_cast<uint64_t>(std::get<1>(k)) * 19349663u ^
                       static_cast<uint64_t>(std::get<2>(k)) * 83492791u;
    return static_cast<size_t>(h ^ (h >> 29));
  }
  double cell_;
  std::vector<int> slot_;
  size_t mask_ = 0;
  std::vector<Key> keys_;
  std::vector<int> start_;
  std::vector<double> x_, y_, z_, q_;
};

// Mode of the quality-weighted Gaussian kernel density f(x) = Σ q_i exp(−|x_i − x|² / 2h²) at bandwidth h,
// then h/2 and h/4 (each from the last). The plain mean-shift step (Σ q K x_i / Σ q K − x) converges
// linearly, and slowly on the elongated clusters of a straight aperture (≈ 0.9 per iteration along the
// range: after 30 iterations it was still centimetres short of the h/4 mode). Newton's step on f —
// gradient g = Σ q K (x_i − x) / h², Hessian H = Σ q K ((x_i − x)(x_i − x)ᵀ / h⁴ − I / h²) — converges
// quadratically to the same mode; it is taken where H is negative definite and the step stays within h,
// the mean-shift step (always uphill) otherwise.
// The mode at one bandwidth h from x.
// `known`: modes already reached at this h; a path that comes within `capture_m` of one ends there (it is that
// mode's basin: the rest of the iterations would only converge onto it).
Vec3 shift_at(const CellIndex& grid, Vec3 x, double h, long z_cells, const std::vector<Vec3>* known = nullptr,
              double capture_m = 0.0) {
  // Sized once for every point of the set: the gather below writes without a capacity check per point.
  thread_local std::vector<double> offset_x, offset_y, offset_z, exponent, quality, w_buffer;
  const size_t capacity = static_cast<size_t>(grid.points());
  if (offset_x.size() < capacity)
    for (auto* v : {&offset_x, &offset_y, &offset_z, &exponent, &quality, &w_buffer}) v->resize(capacity);
  const double cut2 = 9.0 * h * h;
  for (int it = 0; it < 30; ++it) {
    const Key c = grid.key(x);
    const long reach = static_cast<long>(std::ceil(3.0 * h / grid.cell()));
    const long reach_z = std::min(reach, z_cells);
    // Gather the kernel's support first, then its weights in one vectorised exp (a libm call per point
    // was most of this function's time).
    Eigen::Index m = 0;
    double* ox = offset_x.data();
    double* oy = offset_y.data();
    double* oz = offset_z.data();
    double* ex = exponent.data();
    double* q = quality.data();
    for (long dx = -reach; dx <= reach; ++dx)
      for (long dy = -reach; dy <= reach; ++dy)
        for (long dz = -reach_z; dz <= reach_z; ++dz) {
          const int found = grid.find({std::get<0>(c) + dx, std::get<1>(c) + dy, std::get<2>(c) + dz});
          if (found < 0) continue;
          for (int k = grid.begin(found); k < grid.end(found); ++k) {
            // The kernel is cut at 3h (what `reach` visits): beyond it exp(−4.5) ≈ 1 % adds nothing but cost
            // and makes the sum depend on the cell boundaries.
            // Written unconditionally and kept by advancing m (no branch to mispredict at the cut's edge; a
            // point beyond it is overwritten by the next).
            const Vec3 d = Vec3(grid.x(k), grid.y(k), grid.z(k)) - x;
            const double d2 = d.squaredNorm();
            ox[m] = d.x(), oy[m] = d.y(), oz[m] = d.z();
            ex[m] = -0.5 * d2 / (h * h);
            q[m] = grid.quality(k);
            m += !(d2 > cut2);
          }
        }
    Eigen::Map<Eigen::ArrayXd> weights(w_buffer.data(), m);
    weights = Eigen::Map<const Eigen::ArrayXd>(quality.data(), m) * Eigen::Map<const Eigen::ArrayXd>(exponent.data(), m).exp();
    // Plain scalar sums (Σw, Σw d, Σw d dᵀ): as Eigen temporaries they were kept on the stack and every
    // iteration waited on the store of the one before.
    double den = 0.0, nx = 0.0, ny = 0.0, nz = 0.0, sxx = 0.0, sxy = 0.0, sxz = 0.0, syy = 0.0, syz = 0.0, szz = 0.0;
    for (Eigen::Index k = 0; k < m; ++k) {
      const double w = weights[k], ex = ox[k], ey = oy[k], ez = oz[k];
      den += w;
      nx += w * ex, ny += w * ey, nz += w * ez;
      sxx += w * ex * ex, sxy += w * ex * ey, sxz += w * ex * ez;
      syy += w * ey * ey, syz += w * ey * ez, szz += w * ez * ez;
    }
    const Vec3 num(nx, ny, nz);
    Eigen::Matrix3d scatter;
    scatter << sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz;
    if (den <= 0.0) break;
    const Vec3 mean_shift = num / den;
    // −H h² / den = I − scatter / (h² den); Newton: step = −H⁻¹ g = (I − scatter / (h² den))⁻¹ · mean_shift.
    const Eigen::Matrix3d neg_h = Eigen::Matrix3d::Identity() - scatter / (h * h * den);
    Vec3 step = mean_shift;
    const Eigen::LLT<Eigen::Matrix3d> llt(neg_h);
    if (llt.info() == Eigen::Success) {
      const Vec3 newton = llt.solve(mean_shift);
      if (newton.allFinite() && newton.norm() <= h) step = newton;
    }
    x += step;
    if (step.norm() < 1e-6) break;  // 1 µm: far below the cluster spread; the joint fit polishes the point
    if (known)
      for (const Vec3& m : *known)
        if ((x - m).norm() < capture_m) return m;
  }
  return x;
}

// The mode at h, then refined at h/2 and h/4.
Vec3 refine_mode(const CellIndex& grid, Vec3 x, double bandwidth_m, long z_cells) {
  for (double h : {bandwidth_m / 2.0, bandwidth_m / 4.0}) x = shift_at(grid, x, h, z_cells);
  return x;
}

Vec3 shift_to_mode(const CellIndex& grid, Vec3 x, double bandwidth_m, long z_cells) {
  return refine_mode(grid, shift_at(grid, x, bandwidth_m, z_cells), bandwidth_m, z_cells);
}

}  // namespace

Vec3 intersection_mode_near(const std::vector<Intersection>& set, const Vec3& start, double bandwidth_m) {
  const CellIndex grid(set, bandwidth_m);
  return shift_to_mode(grid, start, bandwidth_m, grid.z_span());
}

std::vector<Vec3> intersection_modes(const std::vector<Intersection>& set, double bandwidth_m, int max_modes) {
  std::vector<Vec3> modes;
  if (set.empty()) return modes;
  const double cell = bandwidth_m;
  const CellIndex grid(set, cell);
  const long z_cells = grid.z_span();
  const long reach_z = std::min(1L, z_cells);
  // Kernel-density score of each occupied cell: quality summed over the 3×3×3 neighbourhood (3×3 when planar).
  struct Scored {
    double score;
    Key key;
    int cell;
  };
  std::vector<Scored> scored;
  scored.reserve(grid.cells());
  for (int c = 0; c < grid.cells(); ++c) {
    const Key& k = grid.cell_key(c);
    double s = 0.0;
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -reach_z; dz <= reach_z; ++dz) {
          const int n = grid.find({std::get<0>(k) + dx, std::get<1>(k) + dy, std::get<2>(k) + dz});
          if (n >= 0)
            for (int i = grid.begin(n); i < grid.end(n); ++i) s += grid.quality(i);
        }
    scored.push_back(Scored{s, k, c});
  }
  std::sort(scored.begin(), scored.end(), [](const Scored& a, const Scored& b) {
    return a.score != b.score ? a.score > b.score : a.key < b.key;
  });
  std::vector<Vec3> modes_at_h;
  for (const auto& [score, k, c] : scored) {
    if (static_cast<int>(modes.size()) >= max_modes) break;
    // Seeds are the dense cells: a cell with under a tenth of the densest one's intersection weight holds the
    // scatter of near-parallel conics, not a cluster (the mirror and grating-lobe clusters are as dense as
    // the true one, so they are still seeded).
    if (score < 0.1 * scored.front().score) break;
    Vec3 start = Vec3::Zero();
    double w = 0.0;
    for (int i = grid.begin(c); i < grid.end(c); ++i)
      start += grid.quality(i) * Vec3(grid.x(i), grid.y(i), grid.z(i)), w += grid.quality(i);
    start /= w;
    // A start within one bandwidth of a mode already found lies in its basin: shifting it again would only
    // find that mode (the distinctness test below needs 2 bandwidths).
    bool known = false;
    for (const Vec3& m : modes) known |= (m - start).norm() < bandwidth_m;
    if (known) continue;
    // Seeds of one cluster reach the same mode at h; refining it again (deterministic from there) would
    // only give the same point, which the distinctness test drops.
    const Vec3 at_h = shift_at(grid, start, bandwidth_m, z_cells, &modes_at_h, 1e-3 * bandwidth_m);
    bool reached = false;
    for (const Vec3& m : modes_at_h) reached |= (m - at_h).norm() < 1e-5;
    if (reached) continue;
    modes_at_h.push_back(at_h);
    const Vec3 x = refine_mode(grid, at_h, bandwidth_m, z_cells);
    bool distinct = true;
    for (const Vec3& m : modes) distinct &= (m - x).norm() > 2.0 * bandwidth_m;
    if (distinct) modes.push_back(x);
  }
  return modes;
}

LocalizeResult localize_hyperbolic(const TagReads& tag, const LocalizeOptions& options) {
  // With a calibration the conics start at the phase centre; its pattern needs the unknown direction and is
  // removed below, from the estimate.
  TagReads shifted;
  if (options.calibration) {
    shifted = tag;
    for (ReadGroup& g : shifted.groups)
      if (options.calibration->antenna.empty() || options.calibration->antenna == g.antenna)
        for (PhaseRead& r : g.reads) r.antenna_m = options.calibration->phase_centre(r.antenna_m, r.antenna_orientation);
  }
  const TagReads& reads = options.calibration ? shifted : tag;
  PreparedTag prep;
  std::vector<Intersection> set;
  std::vector<Vec3> modes;
  // The paper's pipeline on `r`: unwrap, conics, their intersections, the cluster modes.
  auto intersect = [&](const TagReads& r) -> std::optional<LocalizeResult> {
    prep = PreparedTag{};
    if (auto fail = prepare(r, options, prep)) return *fail;
    double plane_z = options.tag_height_m;
    if (!options.height_known) {
      plane_z = 0.0;
      for (const Vec3& p : prep.positions) plane_z += p.z();
      plane_z /= static_cast<double>(prep.positions.size());
    }
    double stride = 0.0;
    const std::vector<Hyperbola> conics = build_conics(prep, options, &stride);
    const int need = options.height_known ? 3 : 4;  // ≥ 2 (2-D) / 3 (3-D) conics plus one to cross-check
    if (static_cast<int>(conics.size()) < need) {
      std::ostringstream why;
      why << conics.size() << " conics at stride " << stride << " m, need " << need;
      LocalizeResult f = LocalizeResult::failure(FailReason::kApertureTooShort, why.str());
      f.reads_used = prep.usable_reads;
      return f;
    }
    set = intersect_conics(conics, options, plane_z);
    modes = intersection_modes(set, options.cluster_bandwidth_m, 5);
    // Every intersection lies in the plane z = tag height; the weighted means of the mode search only round off.
    if (options.height_known)
      for (Vec3& m : modes) m.z() = options.tag_height_m;
    if (modes.empty()) {
      LocalizeResult f = LocalizeResult::failure(FailReason::kNoConvergence,
                                                 std::to_string(conics.size()) + " conics have no intersection in range");
      f.reads_used = prep.usable_reads;
      return f;
    }
    return std::nullopt;
  };
  auto best_mode = [&]() {
    RangeCost c(prep, options.height_known, options.tag_height_m);
    double best = std::numeric_limits<double>::infinity();
    Vec3 at = modes.front();
    for (const Vec3& m : modes) {
      const double v = c.ssr(m);
      if (v < best) best = v, at = m;
    }
    return at;
  };
  if (auto fail = intersect(reads)) return *fail;
  // A calibrated phase pattern bends every read's phase by pattern(direction to the tag), unknown before the
  // tag is: it is removed at the estimate and the conics intersected again, from each new estimate until it
  // moves less than 1 mm (at most 4 times: the direction error of the first estimate leaves part of the
  // pattern in, a 7 cm error left 3 cm).
  const bool has_pattern = options.calibration && !options.fold_pi &&
                           std::any_of(options.calibration->pattern_rad.begin(), options.calibration->pattern_rad.end(),
                                       [](double c) { return c != 0.0; });
  TagReads corrected;
  if (has_pattern) {
    Vec3 at = best_mode();
    for (int pass = 0; pass < 4; ++pass) {
      corrected = reads;
      for (ReadGroup& g : corrected.groups)
        if (options.calibration->antenna.empty() || options.calibration->antenna == g.antenna)
          for (PhaseRead& r : g.reads) {
            double az, el;
            direction_in_frame(r.antenna_m, r.antenna_orientation, at, az, el);
            r.phase_rad -= options.calibration->pattern_phase_rad(az, el);
          }
      if (auto fail = intersect(corrected)) return *fail;
      const Vec3 next = best_mode();
      const double moved_m = (next - at).norm();
      at = next;
      if (moved_m < 1e-3) break;
    }
  }
  RangeCost cost(prep, options.height_known, options.tag_height_m);
  LocalizeResult result;
  result.position = best_mode();
  result.ok = true;
  const Vec3 own = result.position;
  SoftGate soft;  // cycle slips / predicted σ: the joint judgement still gives a position and radius (uncertain)
  finish_unwrapped(result, prep, cost, options, true, &soft);
  // A prior that picked the mirror side picked the least-squares mirror point: report instead the mode of
  // this method's own intersection set there (the mirror cluster exists: conics are mirror-symmetric).
  if (result.ok && !result.mirror_resolved_by.empty() && (result.position - own).norm() > 0.0)
    result.position = intersection_mode_near(set, result.position, options.cluster_bandwidth_m);
  if (options.height_known) result.position.z() = options.tag_height_m;
  // Honest uncertainty from the joint multi-carrier model: the region of its optimum reached from this
  // estimate, grown by the distance to it (the cluster mode is not the least-squares point); the same
  // consistency and uniqueness judgement (other cluster modes are the rivals).
  if (result.ok) {
    const JointModel model = make_joint_model(tag, options);
    const Vec3 focused = focus_near(model, result.position, model.min_wavelength_m() / 8.0, options.height_known,
                                    focus_min_step_m(model));
    const JointFit fit = fit_joint(model, focused, options);
    judge_joint(result, model, fit, modes, prep, options, true);
    apply_soft_gate(result, soft);
  }
  return result;
}

}  // namespace rfidray::loc
