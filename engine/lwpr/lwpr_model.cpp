// LWPR model: per-output receptive field sets, creation, pruning, blended prediction.
#include "engine/lwpr/lwpr_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <utility>

namespace armfarm::lwpr {
namespace {

void require_vector(const Eigen::VectorXd& v, int size, const char* name) {
  if (v.size() != size) {
    throw std::invalid_argument(std::string("LWPR: ") + name + " has " + std::to_string(v.size()) +
                                " elements, expected " + std::to_string(size));
  }
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v(i))) {
      throw std::invalid_argument(std::string("LWPR: ") + name + "[" + std::to_string(i) + "] is not finite");
    }
  }
}

// trace D of a ReceptiveField or a LaneField (a diagonal metric is one column).
template <class Field>
double calc_trace(const Field& rf) {
  return rf.metric.cols() == 1 ? rf.metric.sum() : rf.metric.trace();
}

// The diagonal scan sums each field's q in blocks of kScanBlock input elements (the early exit
// is checked once per block) and runs kScanGroup fields side by side, one per vector lane.
constexpr int kScanBlock = 8;
constexpr int kScanGroup = 4;

// One double per field of a scan group, operated on lane by lane (a GCC/Clang vector extension:
// the compiler maps it to the vector units the build targets, two SSE2 operations portably, one
// in the AVX2 copy), with the same result in every lane; and the lane mask a comparison gives.
typedef double GroupLanes __attribute__((vector_size(kScanGroup * sizeof(double))));
typedef decltype(GroupLanes{} >= GroupLanes{}) GroupMask;

constexpr unsigned kAllLanes = (1u << kScanGroup) - 1;

// Bit l set when lane l of the mask is set: the sign bits of its two halves (SSE2's movmskpd,
// which the portable and the AVX2 copy both have; a lane-by-lane loop compiles to four extracts).
inline unsigned lane_bits(const GroupMask& m) {
  static_assert(kScanGroup == 4, "two halves of two lanes");
  typedef double Half __attribute__((vector_size(2 * sizeof(double))));
  Half low, high;
  std::memcpy(&low, &m, sizeof low);
  std::memcpy(&high, reinterpret_cast<const char*>(&m) + sizeof low, sizeof high);
  return static_cast<unsigned>(__builtin_ia32_movmskpd(low) | (__builtin_ia32_movmskpd(high) << 2));
}

// Sets `out` to the mask with lane l set where bit l of `bits` is clear (by reference, as
// calc_group_distances() below).
inline void set_lanes_without(unsigned bits, GroupMask& out) {
  typedef std::remove_reference_t<decltype(GroupMask{}[0])> Lane;
  const GroupMask lane_bit = {1, 2, 4, 8};
  out = (lane_bit & static_cast<Lane>(bits)) == 0;
}

// q_l = Σ_i d_l,i (x_i − c_l,i)² for the kScanGroup fields of one group (lane l: field l), c and d
// in the group layout (element i of lane l at [i·kScanGroup + l]), `stride` a multiple of
// kScanBlock (zero-padded), `limit` q_limit in every lane. Lane l's q is summed in one order
// whatever the vector width: each block's eight products in a fixed tree, the blocks in order.
// `out` holds the lanes already excluded on entry and gets every lane whose q reached q_limit at
// the end of a block (there one field's scan stopped and returned +∞); the loop stops once every
// lane is out. The vectors go by reference (a vector returned by value can change the call ABI
// between builds).
__attribute__((always_inline)) inline void calc_group_distances(const double* x, const double* c, const double* d,
                                                                int stride, const GroupLanes& limit,
                                                                GroupLanes& q, GroupMask& out) {
  q = GroupLanes{};
  for (int b = 0; b < stride; b += kScanBlock) {
    GroupLanes part[kScanBlock];
    for (int k = 0; k < kScanBlock; ++k) {
      GroupLanes cv, dv;
      std::memcpy(&cv, c + (b + k) * kScanGroup, sizeof cv);
      std::memcpy(&dv, d + (b + k) * kScanGroup, sizeof dv);
      const GroupLanes diff = x[b + k] - cv;
      part[k] = dv * diff * diff;
    }
    q += ((part[0] + part[1]) + (part[2] + part[3])) + ((part[4] + part[5]) + (part[6] + part[7]));
    out |= q >= limit;
    if (lane_bits(out) == kAllLanes) break;
  }
}

// q_l = |M_l(x − c_l)|² for the kScanGroup fields of one group with full metrics: each field's
// upper triangular factor M stored row by row (row r holds M_r,r … M_r,n−1: n(n+1)/2 elements),
// element j of lane l at m[j·kScanGroup + l], the centres in the group layout. Each lane runs a
// field's own operations in their order: diff_k = x_k − c_k, each row's product summed in
// ascending column order, q summed row by row; a lane is out once q ≥ q_limit at the end of a row
// (q only grows), and the rows stop once every lane is out (n > 2). N > 0 fixes n at compile time
// (unrolled, the differences in registers), N = 0 takes n_runtime and keeps the differences in
// `diff` (n·kScanGroup doubles). `out` as calc_group_distances().
template <int N>
__attribute__((always_inline)) inline void calc_group_full_distances(const double* x, const double* c,
                                                                     const double* m, int n_runtime,
                                                                     const GroupLanes& limit, double* diff,
                                                                     GroupLanes& q, GroupMask& out) {
  const int n = N > 0 ? N : n_runtime;
  GroupLanes fixed[N > 0 ? N : 1];
  auto load_diff = [&](int k, GroupLanes& d) __attribute__((always_inline)) {
    if constexpr (N > 0) {
      d = fixed[k];
    } else {
      std::memcpy(&d, diff + k * kScanGroup, sizeof d);
    }
  };
  for (int k = 0; k < n; ++k) {
    GroupLanes cv;
    std::memcpy(&cv, c + k * kScanGroup, sizeof cv);
    const GroupLanes d = x[k] - cv;
    if constexpr (N > 0) {
      fixed[k] = d;
    } else {
      std::memcpy(diff + k * kScanGroup, &d, sizeof d);
    }
  }
  for (int r = 0; r < n; ++r) {
    GroupLanes mv, d;
    std::memcpy(&mv, m, sizeof mv);
    load_diff(r, d);
    GroupLanes v = mv * d;
    for (int k = r + 1; k < n; ++k) {
      std::memcpy(&mv, m + (k - r) * kScanGroup, sizeof mv);
      load_diff(k, d);
      v += mv * d;
    }
    m += (n - r) * kScanGroup;
    if (r == 0) {
      q = v * v;  // the field-wise sum's 0 + v²: the same bits (v² is +0, positive or NaN, never −0)
    } else {
      q += v * v;
    }
    out |= q >= limit;
    // Not at n = 2: on the cross function a group's lanes were all out after its first row in
    // about one group of nine, so the test cost more than the row it saved (callgrind).
    if (N != 2 && r + 1 < n && lane_bits(out) == kAllLanes) return;
  }
}

// One output's scan over its groups: `distances(c, m, q, out)` gives a group's q (centres at c,
// metrics at m) with `out` as calc_group_distances(); the lanes inside get their activation, and
// the fields with w > cutoff are appended in field order. `trusted_lanes` holds one byte per group
// (bit l: lane l's field is trustworthy); with TrustedOnly a group's other lanes start out and a
// group without a trustworthy field is skipped.
template <bool TrustedOnly, class Distances>
__attribute__((always_inline)) inline void scan_groups(std::size_t count, const double* centres,
                                                       std::size_t centre_stride, const double* metrics,
                                                       std::size_t metric_stride, const unsigned char* trusted_lanes,
                                                       Kernel kernel, double cutoff, std::vector<ActiveField>& active,
                                                       Distances&& distances) {
  for (std::size_t first = 0, g = 0; first < count; first += kScanGroup, ++g) {
    GroupMask out = {};  // lanes past the last field, or untrusted ones when only trusted ones count
    if constexpr (TrustedOnly) {
      const unsigned bits = trusted_lanes[g];
      if (bits == 0) continue;
      if (bits != kAllLanes) set_lanes_without(bits, out);
    } else if (first + kScanGroup > count) {
      set_lanes_without((1u << (count - first)) - 1, out);
    }
    GroupLanes q;
    distances(centres + first * centre_stride, metrics + first * metric_stride, q, out);
    unsigned inside = ~lane_bits(out) & kAllLanes;
    while (inside != 0) {
      const int l = __builtin_ctz(inside);
      inside &= inside - 1;
      const double w = calc_kernel(kernel, q[l]);
      if (!(w <= cutoff) && w > 0.0) active.push_back({first + static_cast<std::size_t>(l), w});
    }
  }
}

// Writes M's upper triangle row by row into one lane of the group layout (element j at
// to[j·kScanGroup]); after every metric step, so n = 2 and 3 are fixed sizes (N > 0; a dynamic
// loop's control was most of it), other n run with n_runtime.
template <int N>
__attribute__((always_inline)) inline void copy_upper_triangle(const Eigen::MatrixXd& M, int n_runtime, double* to) {
  const int n = N > 0 ? N : n_runtime;
  const double* column = M.data();
  const auto rows = static_cast<std::size_t>(M.rows());
  for (int r = 0; r < n; ++r) {
    for (int k = r; k < n; ++k, to += kScanGroup) *to = column[static_cast<std::size_t>(k) * rows + r];  // M(r, k)
  }
}

}  // namespace

LwprModel::LwprModel(int n_in, int n_out, const LwprParams& params, FieldLayout layout)
    : n_in_(n_in), n_out_(n_out), params_(params) {
  validate_lwpr_params(params_, n_in, n_out);
  init_metric_ = calc_init_metric(params_, n_in);
  norm_in_ = calc_norm_vector(params_.norm_in, n_in);
  norm_out_ = calc_norm_vector(params_.norm_out, n_out);
  trust_n_data_ = params_.trust_n_data > 0.0 ? params_.trust_n_data : 2.0 * n_in;
  fields_.resize(n_out);
  scan_.resize(n_out);
  stride_ = (n_in + kScanBlock - 1) / kScanBlock * kScanBlock;
  diagonal_scan_ = params_.diag_only || n_in == 1;  // a 1×1 metric is its own diagonal (ReceptiveField::diagonal)
  metric_stride_ = diagonal_scan_ ? stride_ : n_in * (n_in + 1) / 2;
  q_limit_ = calc_q_limit(params_.kernel, params_.cutoff);
  x_normalised_.resize(n_in);
  x_padded_.assign(stride_, 0.0);
  scratch_.resize(n_in, params_.diag_only);
  for (FieldScratch& s : group_scratch_) s.resize(n_in, params_.diag_only);
  scan_diff_.assign(static_cast<std::size_t>(n_in) * kScanGroup, 0.0);
  shared_scan_ = !params_.update_D;
  lane_layout_ = layout == FieldLayout::kAuto && shared_scan_ && n_in > 3 && n_out >= 2;
  if (lane_layout_) {
    lane_scratch_.resize(n_in);
    lane_scratch_pair_.resize(n_in);
    y_normalised_.assign(n_out, 0.0);
  }
}

std::size_t LwprModel::calc_group_offset(std::size_t i) const {
  return (i / kScanGroup) * static_cast<std::size_t>(stride_) * kScanGroup + i % kScanGroup;
}

std::size_t LwprModel::calc_metric_offset(std::size_t i) const {
  return (i / kScanGroup) * static_cast<std::size_t>(metric_stride_) * kScanGroup + i % kScanGroup;
}

template <class Field>
inline void LwprModel::write_scan_metric(int output, std::size_t i, const Field& rf) {
  double* to = scan_[output].metrics.data() + calc_metric_offset(i);
  if (diagonal_scan_) {
    for (int k = 0; k < n_in_; ++k) to[k * kScanGroup] = rf.metric(k, 0);
    return;
  }
  if (n_in_ == 2) {
    copy_upper_triangle<2>(rf.metric_factor, 2, to);
  } else if (n_in_ == 3) {
    copy_upper_triangle<3>(rf.metric_factor, 3, to);
  } else {
    copy_upper_triangle<0>(rf.metric_factor, n_in_, to);
  }
}

void LwprModel::write_scan_trust(ScanData& scan, std::size_t i, bool trusted) {
  scan.trusted[i] = trusted ? 1 : 0;
  const auto bit = static_cast<unsigned char>(1u << (i % kScanGroup));
  unsigned char& lanes = scan.trusted_lanes[i / kScanGroup];
  lanes = static_cast<unsigned char>(trusted ? lanes | bit : lanes & ~bit);
}

template <class Field>
void LwprModel::append_to_scan(int output, const Field& rf) {
  ScanData& scan = scan_[output];
  const std::size_t i = scan.trusted.size();
  if (i % kScanGroup == 0) {  // a new group, zero-filled: padding lanes and elements stay 0
    scan.centres.resize(scan.centres.size() + static_cast<std::size_t>(stride_) * kScanGroup, 0.0);
    scan.metrics.resize(scan.metrics.size() + static_cast<std::size_t>(metric_stride_) * kScanGroup, 0.0);
    scan.trusted_lanes.push_back(0);
  }
  scan.trusted.push_back(0);
  write_scan_trust(scan, i, rf.trustworthy);
  double* centre = scan.centres.data() + calc_group_offset(i);
  for (int k = 0; k < n_in_; ++k) centre[k * kScanGroup] = rf.center(k);
  write_scan_metric(output, i, rf);
}

void LwprModel::erase_from_scan(int output, std::size_t victim) {
  ScanData& scan = scan_[output];
  const std::size_t last = scan.trusted.size() - 1;
  // The group layout: every later field moves down one lane, the last slot is cleared, and an
  // emptied group is dropped.
  auto shift_down = [&](std::vector<double>& data, int elements) {
    auto offset = [&](std::size_t j) {
      return (j / kScanGroup) * static_cast<std::size_t>(elements) * kScanGroup + j % kScanGroup;
    };
    for (std::size_t j = victim; j < last; ++j) {
      const double* from = data.data() + offset(j + 1);
      double* to = data.data() + offset(j);
      for (int k = 0; k < elements; ++k) to[k * kScanGroup] = from[k * kScanGroup];
    }
    double* cleared = data.data() + offset(last);
    for (int k = 0; k < elements; ++k) cleared[k * kScanGroup] = 0.0;
    if (last % kScanGroup == 0) data.resize(data.size() - static_cast<std::size_t>(elements) * kScanGroup);
  };
  shift_down(scan.centres, stride_);
  shift_down(scan.metrics, metric_stride_);
  scan.trusted.erase(scan.trusted.begin() + static_cast<std::ptrdiff_t>(victim));
  scan.trusted_lanes.resize((last + kScanGroup - 1) / kScanGroup);
  for (std::size_t g = victim / kScanGroup; g < scan.trusted_lanes.size(); ++g) {
    unsigned bits = 0;
    for (std::size_t j = g * kScanGroup; j < std::min(last, (g + 1) * kScanGroup); ++j) {
      bits |= (scan.trusted[j] != 0 ? 1u : 0u) << (j % kScanGroup);
    }
    scan.trusted_lanes[g] = static_cast<unsigned char>(bits);
  }
}

LwprModel::LwprModel(int n_in, int n_out, const LwprParams& params, std::vector<std::vector<ReceptiveField>> fields,
                     std::uint64_t n_updates, FieldLayout layout)
    : LwprModel(n_in, n_out, params, layout) {
  if (static_cast<int>(fields.size()) != n_out) {
    throw std::invalid_argument("LWPR: " + std::to_string(fields.size()) + " field lists for " +
                                std::to_string(n_out) + " outputs");
  }
  const Eigen::Index metric_cols = params_.diag_only ? 1 : n_in;
  for (const auto& list : fields) {
    for (const ReceptiveField& rf : list) {
      const int r = rf.n_reg();
      const bool ok = rf.center.size() == n_in && rf.metric.rows() == n_in && rf.metric.cols() == metric_cols &&
                      rf.metric_factor.rows() == n_in && rf.metric_factor.cols() == metric_cols &&
                      rf.log_alpha.rows() == n_in && rf.log_alpha.cols() == metric_cols &&
                      rf.meta_trace.rows() == n_in && rf.meta_trace.cols() == metric_cols &&
                      rf.mean_x.size() == n_in && r >= 1 && r <= n_in && rf.sum_w.size() == r &&
                      rf.n_data.size() == r && rf.sxy.rows() == n_in && rf.sxy.cols() == r &&
                      rf.sxs.rows() == n_in && rf.sxs.cols() == r && rf.sys.size() == r &&
                      rf.sum_e_cv2.size() == r && rf.press_H.size() == r && rf.press_R.size() == r &&
                      rf.directions.rows() == n_in && rf.directions.cols() == r && rf.loadings.rows() == n_in &&
                      rf.loadings.cols() == r && rf.beta.size() == r;
      if (!ok) throw std::invalid_argument("LWPR: a receptive field's sizes do not match the model");
    }
  }
  n_updates_ = n_updates;
  if (lane_layout_) {
    // The lane form only if every field's copies agree on what the outputs share (a model this
    // class trained without update_D always does); else one list per output.
    bool agree = true;
    for (int o = 1; o < n_out && agree; ++o) agree = fields[o].size() == fields[0].size();
    std::vector<const ReceptiveField*> copies(n_out);
    for (std::size_t i = 0; agree && i < fields[0].size(); ++i) {
      for (int o = 0; o < n_out; ++o) copies[o] = &fields[o][i];
      agree = lane_copies_agree(copies);
    }
    if (agree) {
      lane_fields_.reserve(fields[0].size());
      for (std::size_t i = 0; i < fields[0].size(); ++i) {
        for (int o = 0; o < n_out; ++o) copies[o] = &fields[o][i];
        lane_fields_.push_back(pack_lane_field(copies));
        append_to_scan(0, lane_fields_.back());
      }
      return;
    }
    lane_layout_ = false;
  }
  fields_ = std::move(fields);
  for (int o = 0; o < n_out; ++o) {
    for (const ReceptiveField& rf : fields_[o]) append_to_scan(o, rf);
  }
  shared_scan_ = !params_.update_D && calc_scans_identical();
}

bool LwprModel::calc_scans_identical() const {
  for (int o = 1; o < n_out_; ++o) {
    if (scan_[o].centres != scan_[0].centres || scan_[o].metrics != scan_[0].metrics ||
        scan_[o].trusted != scan_[0].trusted) {
      return false;
    }
  }
  return true;
}

void LwprModel::scan_active(int output, const double* x_padded, bool trusted_only, bool avx2, double* diff,
                            std::vector<ActiveField>& active) const {
  if (avx2) {
    scan_active_avx2(output, x_padded, trusted_only, diff, active);
  } else {
    scan_active_loop(output, x_padded, trusted_only, diff, active);
  }
}

void LwprModel::scan_active_avx2(int output, const double* x_padded, bool trusted_only, double* diff,
                                 std::vector<ActiveField>& active) const {
  scan_active_loop(output, x_padded, trusted_only, diff, active);
}

inline void LwprModel::scan_active_loop(int output, const double* x_padded, bool trusted_only, double* diff,
                                        std::vector<ActiveField>& active) const {
  active.clear();
  const ScanData& scan = scan_[output];
  const double* x = x_padded;
  const GroupLanes limit = GroupLanes{} + q_limit_;  // q_limit in every lane
  auto scan_with = [&](auto&& distances) __attribute__((always_inline)) {
    const std::size_t count = scan.trusted.size();
    const auto centre_stride = static_cast<std::size_t>(stride_);
    const auto metric_stride = static_cast<std::size_t>(metric_stride_);
    if (trusted_only) {
      scan_groups<true>(count, scan.centres.data(), centre_stride, scan.metrics.data(), metric_stride,
                        scan.trusted_lanes.data(), params_.kernel, params_.cutoff, active, distances);
    } else {
      scan_groups<false>(count, scan.centres.data(), centre_stride, scan.metrics.data(), metric_stride,
                         scan.trusted_lanes.data(), params_.kernel, params_.cutoff, active, distances);
    }
  };
  const int n = n_in_;
  const int stride = stride_;
  if (diagonal_scan_) {
    scan_with([&](const double* c, const double* m, GroupLanes& q, GroupMask& out) __attribute__((always_inline)) {
      calc_group_distances(x, c, m, stride, limit, q, out);
    });
  } else if (n == 2) {
    scan_with([&](const double* c, const double* m, GroupLanes& q, GroupMask& out) __attribute__((always_inline)) {
      calc_group_full_distances<2>(x, c, m, 2, limit, diff, q, out);
    });
  } else if (n == 3) {
    scan_with([&](const double* c, const double* m, GroupLanes& q, GroupMask& out) __attribute__((always_inline)) {
      calc_group_full_distances<3>(x, c, m, 3, limit, diff, q, out);
    });
  } else {
    scan_with([&](const double* c, const double* m, GroupLanes& q, GroupMask& out) __attribute__((always_inline)) {
      calc_group_full_distances<0>(x, c, m, n, limit, diff, q, out);
    });
  }
}

inline void LwprModel::normalise_input(const Eigen::VectorXd& x, double* normalised, double* padded) const {
  for (int i = 0; i < n_in_; ++i) {
    const double v = x(i);
    if (!std::isfinite(v)) require_vector(x, n_in_, "x");  // throws, naming the first such element
    normalised[i] = v / norm_in_(i);  // x.cwiseQuotient(norm_in_)
    padded[i] = normalised[i];
  }
}

void LwprModel::update(const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  // require_vector(x), then require_vector(y): the same checks in the same order, x's finiteness
  // inside the normalisation loop (x_normalised_ and x_padded_ are scratch: the model is
  // unchanged when y is refused after them).
  if (x.size() != n_in_) require_vector(x, n_in_, "x");
  normalise_input(x, x_normalised_.data(), x_padded_.data());
  if (y.size() != n_out_) require_vector(y, n_out_, "y");
  for (int o = 0; o < n_out_; ++o) {
    if (!std::isfinite(y(o))) require_vector(y, n_out_, "y");
  }
  if (shared_scan_) scan_active(0, x_padded_.data(), false, scratch_.use_avx2, scan_diff_.data(), active_);
  if (lane_layout_) {
    for (int o = 0; o < n_out_; ++o) y_normalised_[o] = y(o) / norm_out_(o);
    update_lane_fields(y_normalised_.data(), active_);
    ++n_updates_;
    return;
  }
  for (int o = 0; o < n_out_; ++o) {
    if (!shared_scan_) scan_active(o, x_padded_.data(), false, scratch_.use_avx2, scan_diff_.data(), active_);
    update_output(o, y(o) / norm_out_(o), active_);
  }
  ++n_updates_;
}

LwprModel::ActiveSummary LwprModel::update_active_fields(int output, double y, const std::vector<ActiveField>& active) {
  std::vector<ReceptiveField>& fields = fields_[output];
  const Eigen::VectorXd& x = x_normalised_;
  ScanData& scan = scan_[output];
  ActiveSummary summary;
  auto note = [&](const ActiveField& a) { summary.note(a, params_.w_prune); };
  auto after = [&](std::size_t i) {
    if (params_.update_D) write_scan_metric(output, i, fields[i]);
    if ((scan.trusted[i] != 0) != fields[i].trustworthy) write_scan_trust(scan, i, fields[i].trustworthy);
  };
  // kFieldGroup fields at a time (distinct fields: the scan lists each once), each with its own
  // scratch: the same bits as one by one (update_receptive_fields).
  for (std::size_t k = 0; k < active.size(); k += kFieldGroup) {
    const int count = static_cast<int>(std::min<std::size_t>(kFieldGroup, active.size() - k));
    double w[kFieldGroup];
    ReceptiveField* group[kFieldGroup];
    FieldScratch* scratch[kFieldGroup] = {&scratch_};
    for (int j = 0; j < count; ++j) {
      const ActiveField& a = active[k + j];
      note(a);
      w[j] = a.w;
      group[j] = &fields[a.index];
      if (j > 0) scratch[j] = &group_scratch_[j - 1];
    }
    update_receptive_fields(params_, trust_n_data_, x, y, count, w, group, scratch);
    for (int j = 0; j < count; ++j) after(active[k + j].index);
  }
  return summary;
}

void LwprModel::update_output(int output, double y, const std::vector<ActiveField>& active) {
  std::vector<ReceptiveField>& fields = fields_[output];
  const Eigen::VectorXd& x = x_normalised_;
  const ActiveSummary summary = update_active_fields(output, y, active);
  const double w_max = summary.w_max;
  const int i_max = summary.i_max;
  const int prune_a = summary.prune_a;
  const int prune_b = summary.prune_b;

  if (w_max <= params_.w_gen && (params_.max_fields == 0 || fields.size() < params_.max_fields)) {
    // Start from the metric of the nearest field if it is trustworthy and not too far away.
    const bool use_neighbour = i_max >= 0 && w_max > 0.1 * params_.w_gen && fields[i_max].trustworthy;
    Eigen::MatrixXd D;
    if (use_neighbour) {
      const ReceptiveField& near = fields[i_max];
      D = near.diagonal() ? Eigen::MatrixXd(near.metric.col(0).asDiagonal()) : near.metric;
    } else {
      D = init_metric_;
    }
    fields.push_back(make_receptive_field(params_, x, D));
    update_receptive_field(params_, trust_n_data_, x, y, 1.0, fields.back(), scratch_);
    append_to_scan(output, fields.back());
  }

  if (prune_b >= 0) {
    const int victim = calc_trace(fields[prune_a]) >= calc_trace(fields[prune_b]) ? prune_a : prune_b;
    fields.erase(fields.begin() + victim);
    erase_from_scan(output, static_cast<std::size_t>(victim));
  }
}

void LwprModel::update_lane_fields(const double* y, const std::vector<ActiveField>& active) {
  const Eigen::VectorXd& x = x_normalised_;
  ScanData& scan = scan_[0];
  // update_active_fields() and update_output() of every output at once: the active list, the
  // most active field and the pruning candidates are the same for every output.
  ActiveSummary summary;
  auto note = [&](const ActiveField& a) { summary.note(a, params_.w_prune); };
  auto after = [&](std::size_t i) {
    if ((scan.trusted[i] != 0) != lane_fields_[i].trustworthy) write_scan_trust(scan, i, lane_fields_[i].trustworthy);
  };
  std::size_t k = 0;
  for (; k + 1 < active.size(); k += 2) {
    const ActiveField& a = active[k];
    const ActiveField& b = active[k + 1];
    note(a);
    note(b);
    update_lane_field_pair(params_, trust_n_data_, x, y, a.w, lane_fields_[a.index], b.w, lane_fields_[b.index],
                           lane_scratch_, lane_scratch_pair_);
    after(a.index);
    after(b.index);
  }
  if (k < active.size()) {
    note(active[k]);
    update_lane_field(params_, trust_n_data_, x, y, active[k].w, lane_fields_[active[k].index], lane_scratch_);
    after(active[k].index);
  }
  if (summary.w_max <= params_.w_gen && (params_.max_fields == 0 || lane_fields_.size() < params_.max_fields)) {
    const int i_max = summary.i_max;
    const bool use_neighbour =
        i_max >= 0 && summary.w_max > 0.1 * params_.w_gen && lane_fields_[i_max].trustworthy;
    Eigen::MatrixXd D;
    if (use_neighbour) {
      const LaneField& near = lane_fields_[i_max];
      D = near.metric.cols() == 1 ? Eigen::MatrixXd(near.metric.col(0).asDiagonal()) : near.metric;
    } else {
      D = init_metric_;
    }
    const ReceptiveField made = make_receptive_field(params_, x, D);
    lane_fields_.push_back(pack_lane_field(std::vector<const ReceptiveField*>(n_out_, &made)));
    update_lane_field(params_, trust_n_data_, x, y, 1.0, lane_fields_.back(), lane_scratch_);
    append_to_scan(0, lane_fields_.back());
  }
  if (summary.prune_b >= 0) {
    const int victim = calc_trace(lane_fields_[summary.prune_a]) >= calc_trace(lane_fields_[summary.prune_b])
                           ? summary.prune_a
                           : summary.prune_b;
    lane_fields_.erase(lane_fields_.begin() + victim);
    erase_from_scan(0, static_cast<std::size_t>(victim));
  }
}

void LwprModel::ActiveSummary::note(const ActiveField& a, double w_prune) {
  const int i = static_cast<int>(a.index);
  if (a.w > w_max) {
    w_max = a.w;
    i_max = i;
  }
  if (a.w > w_prune) {
    if (prune_a < 0) {
      prune_a = i;
    } else if (prune_b < 0) {
      prune_b = i;
    }
  }
}

std::vector<ReceptiveField> LwprModel::fields(int output) const {
  if (output < 0 || output >= n_out_) throw std::out_of_range("LWPR: no output " + std::to_string(output));
  if (!lane_layout_) return fields_[output];
  std::vector<ReceptiveField> list;
  list.reserve(lane_fields_.size());
  for (const LaneField& f : lane_fields_) list.push_back(unpack_lane_field(f, output));
  return list;
}

std::size_t LwprModel::field_count(int output) const {
  if (output < 0 || output >= n_out_) throw std::out_of_range("LWPR: no output " + std::to_string(output));
  return lane_layout_ ? lane_fields_.size() : fields_[output].size();
}

std::unique_ptr<PredictionWorkspace> LwprModel::make_workspace() const {
  auto workspace = std::make_unique<LwprWorkspace>();
  workspace->x_normalised.resize(n_in_);
  workspace->x_padded.assign(stride_, 0.0);
  workspace->scratch.resize(n_in_, params_.diag_only);
  workspace->scan_diff.assign(static_cast<std::size_t>(n_in_) * kScanGroup, 0.0);
  workspace->active.reserve(field_count(0));
  if (lane_layout_) workspace->lane_scratch.resize(n_in_);
  return workspace;
}

Prediction LwprModel::predict(const Eigen::VectorXd& x, PredictionWorkspace& workspace) const {
  Prediction prediction;
  predict_with(x, workspace, nullptr, true, prediction);
  return prediction;
}

Prediction LwprModel::predict(const Eigen::VectorXd& x, PredictionWorkspace& workspace,
                              LwprPredictionDetail& detail) const {
  Prediction prediction;
  predict_with(x, workspace, &detail, true, prediction);
  return prediction;
}

void LwprModel::predict_into(const Eigen::VectorXd& x, PredictionWorkspace& workspace, Prediction& out) const {
  predict_with(x, workspace, nullptr, true, out);
}

void LwprModel::predict_values_into(const Eigen::VectorXd& x, PredictionWorkspace& workspace, Prediction& out) const {
  predict_with(x, workspace, nullptr, false, out);
}

namespace {

// One output's prediction from its active fields: the weighted sums of the blend and the most
// active field's prediction; the noise variances (and so the confidence) only `with_bounds`.
struct OutputBlend {
  double sum_w = 0.0, sum_wy = 0.0, sum_wyy = 0.0, sum_wvar = 0.0;
  double w_best = 0.0, y_best = 0.0, var_best = 0.0;
};

// Adds one active field's prediction y (activation w, noise variance `variance`) to the blend.
inline void add_to_blend(const LwprParams& params, bool with_bounds, double w, double y, double variance,
                         OutputBlend& b) {
  if (params.blend) {
    b.sum_w += w;
    b.sum_wy += w * y;
    if (with_bounds) {
      b.sum_wyy += w * y * y;
      b.sum_wvar += w * variance;
    }
  }
  if (w > b.w_best) {
    b.w_best = w;
    b.y_best = y;
    b.var_best = variance;
  }
}

OutputBlend blend_fields(const LwprParams& params, const std::vector<ReceptiveField>& fields,
                         const std::vector<ActiveField>& active, const Eigen::VectorXd& xn, bool with_bounds,
                         FieldScratch& scratch) {
  OutputBlend b;
  for (const ActiveField& a : active) {
    const double w = a.w;
    const ReceptiveField& rf = fields[a.index];
    double y = 0.0, variance = 0.0;
    if (with_bounds) {
      double leverage = 0.0;
      y = predict_receptive_field(rf, xn, leverage, scratch);
      variance = calc_field_noise_variance(rf) * (1.0 + w * leverage);
    } else {
      y = predict_receptive_field_value(rf, xn, scratch);
    }
    add_to_blend(params, with_bounds, w, y, variance, b);
  }
  return b;
}

// blend_fields() of output o in the lane form, from the active fields' predictions (`values`,
// `leverages`: active field k's output o at [k·n_out + o], computed once for every output).
OutputBlend blend_lane_fields(const LwprParams& params, const std::vector<LaneField>& fields,
                              const std::vector<ActiveField>& active, int o, int n_out, const double* values,
                              const double* leverages, bool with_bounds) {
  OutputBlend b;
  for (std::size_t k = 0; k < active.size(); ++k) {
    const double w = active[k].w;
    const std::size_t at = k * static_cast<std::size_t>(n_out) + static_cast<std::size_t>(o);
    const double variance =
        with_bounds ? calc_lane_noise_variance(fields[active[k].index], o) * (1.0 + w * leverages[at]) : 0.0;
    add_to_blend(params, with_bounds, w, values[at], variance, b);
  }
  return b;
}

}  // namespace

void LwprModel::predict_with(const Eigen::VectorXd& x, PredictionWorkspace& workspace, LwprPredictionDetail* detail,
                             bool with_bounds, Prediction& prediction) const {
  // The checks of require_vector() and the workspace's, in that order, with the same messages;
  // the finiteness check runs inside the normalisation loop (require_vector() then names the
  // first non-finite element). LwprWorkspace is final: its typeid is the dynamic_cast's test.
  if (x.size() != n_in_) require_vector(x, n_in_, "x");
  if (typeid(workspace) != typeid(LwprWorkspace)) {
    require_vector(x, n_in_, "x");
    throw std::invalid_argument("LWPR: predict() needs a workspace from make_workspace()");
  }
  auto* ws = static_cast<LwprWorkspace*>(&workspace);
  if (ws->x_normalised.size() != n_in_) ws->x_normalised.resize(n_in_);
  if (ws->x_padded.size() != static_cast<std::size_t>(stride_)) ws->x_padded.resize(stride_, 0.0);
  if (ws->scan_diff.size() < static_cast<std::size_t>(n_in_) * kScanGroup) {
    ws->scan_diff.resize(static_cast<std::size_t>(n_in_) * kScanGroup);
  }
  normalise_input(x, ws->x_normalised.data(), ws->x_padded.data());
  const Eigen::VectorXd& xn = ws->x_normalised;

  // Every element of value, confidence and output_trusted is written below (no allocation when
  // the sizes are already n_out).
  prediction.value.resize(n_out_);
  prediction.confidence.resize(with_bounds ? n_out_ : 0);
  prediction.trustworthy = true;
  // (vector<bool>::resize calls its out-of-line fill even when the size is already right)
  if (prediction.output_trusted.size() != static_cast<std::size_t>(n_out_)) prediction.output_trusted.resize(n_out_);
  if (detail != nullptr) {
    detail->max_activation = Eigen::VectorXd::Zero(n_out_);
    detail->trustworthy.assign(n_out_, false);
  }
  double min_of_max = std::numeric_limits<double>::infinity();

  if (lane_layout_) {
    // One scan and one lane prediction per active field serve every output.
    scan_active(0, ws->x_padded.data(), true, ws->scratch.use_avx2, ws->scan_diff.data(), ws->active);
    if (ws->lane_scratch.z.size() < static_cast<std::size_t>(n_in_) * kOutputLanes) ws->lane_scratch.resize(n_in_);
    const std::size_t count = ws->active.size() * static_cast<std::size_t>(n_out_);
    if (ws->lane_values.size() < count) {
      ws->lane_values.resize(count);
      ws->lane_leverages.resize(count);
    }
    for (std::size_t k = 0; k < ws->active.size(); ++k) {
      const std::size_t at = k * static_cast<std::size_t>(n_out_);
      predict_lane_field(lane_fields_[ws->active[k].index], xn, ws->lane_values.data() + at,
                         with_bounds ? ws->lane_leverages.data() + at : nullptr, ws->lane_scratch);
    }
  }
  for (int o = 0; o < n_out_; ++o) {
    if (!lane_layout_ && (o == 0 || !shared_scan_)) {
      scan_active(o, ws->x_padded.data(), true, ws->scratch.use_avx2, ws->scan_diff.data(), ws->active);
    }
    const OutputBlend b =
        lane_layout_ ? blend_lane_fields(params_, lane_fields_, ws->active, o, n_out_, ws->lane_values.data(),
                                         ws->lane_leverages.data(), with_bounds)
                     : blend_fields(params_, fields_[o], ws->active, xn, with_bounds, ws->scratch);
    if (detail != nullptr) detail->max_activation(o) = b.w_best;
    min_of_max = std::min(min_of_max, b.w_best);
    if (b.w_best <= 0.0) {
      prediction.value(o) = 0.0;
      if (with_bounds) prediction.confidence(o) = std::numeric_limits<double>::infinity();
      prediction.output_trusted[o] = false;
      prediction.trustworthy = false;
      continue;
    }
    if (detail != nullptr) detail->trustworthy[o] = true;
    prediction.output_trusted[o] = true;
    const double mean = params_.blend ? b.sum_wy / b.sum_w : b.y_best;
    prediction.value(o) = mean * norm_out_(o);
    if (!with_bounds) continue;
    // Blended: the mean of the fields' noise variances plus their disagreement about the mean.
    const double variance =
        params_.blend ? (b.sum_wvar + std::max(0.0, b.sum_wyy - b.sum_w * mean * mean)) / b.sum_w : b.var_best;
    prediction.confidence(o) = std::sqrt(std::max(0.0, variance)) * norm_out_(o);
  }
  prediction.max_activation = n_out_ > 0 ? min_of_max : 0.0;
}

std::size_t LwprModel::size() const {
  if (lane_layout_) return lane_fields_.size() * static_cast<std::size_t>(n_out_);
  std::size_t total = 0;
  for (const auto& list : fields_) total += list.size();
  return total;
}

std::size_t LwprModel::calc_memory_bytes() const {
  std::size_t doubles = static_cast<std::size_t>(init_metric_.size() + norm_in_.size() + norm_out_.size());
  std::size_t flags = 0;
  for (const LaneField& f : lane_fields_) doubles += count_lane_field_doubles(f);
  for (const auto& list : fields_) {
    for (const ReceptiveField& rf : list) {
      doubles += static_cast<std::size_t>(
          rf.center.size() + rf.metric_factor.size() + rf.metric.size() + rf.log_alpha.size() + rf.meta_trace.size() +
          rf.mean_x.size() + rf.sum_w.size() + rf.n_data.size() + rf.sxy.size() + rf.sxs.size() + rf.ss2.size() +
          rf.sys.size() + rf.sum_e_cv2.size() + rf.press_H.size() + rf.press_R.size() + rf.directions.size() +
          rf.loadings.size() + rf.beta.size());
      doubles += 5;  // lambda, beta0, sum_e2, press_E and the trust flag counted as a number
    }
  }
  // The scan's numbers per field (a centre and a metric, padded to the scan stride), not the
  // group layout's padding lanes: the metric stays the same whatever the layout.
  // (The lane form keeps one scan for all outputs: counted once per output, as one per output is.)
  const std::size_t scans = lane_layout_ ? static_cast<std::size_t>(n_out_) : 1;
  for (const ScanData& scan : scan_) {
    doubles += scans * scan.trusted.size() * static_cast<std::size_t>(stride_ + metric_stride_);
    flags += scans * scan.trusted.size();
  }
  return sizeof(double) * doubles + flags;
}

double LwprModel::calc_mean_projections() const {
  std::size_t fields = 0;
  double projections = 0.0;
  for (const LaneField& f : lane_fields_) {
    for (int o = 0; o < n_out_; ++o) projections += f.n_reg(o);
    fields += static_cast<std::size_t>(n_out_);
  }
  for (const auto& list : fields_) {
    for (const ReceptiveField& rf : list) projections += rf.n_reg();
    fields += list.size();
  }
  return fields == 0 ? 0.0 : projections / static_cast<double>(fields);
}

}  // namespace armfarm::lwpr
