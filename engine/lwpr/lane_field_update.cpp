// PLACEHOLDER on branch lanes39 only (never to reach main): the lane update by unpacking each output copy and
// running update_receptive_field() on it: correct, bit for bit, and about 13x slower. Branch lanekern39 replaces this
// file with the vector kernel: on a merge conflict take lanekern39's file.
#include "engine/lwpr/lane_fields.hpp"
namespace armfarm::lwpr {
void update_lane_field(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x, const double* y,
                       double w, LaneField& field, LaneScratch&) {
  std::vector<ReceptiveField> copies;
  FieldScratch scratch;
  scratch.resize(field.input_dim(), params.diag_only);
  for (int o = 0; o < field.n_out; ++o) {
    copies.push_back(unpack_lane_field(field, o));
    update_receptive_field(params, trust_n_data, x, y[o], w, copies.back(), scratch);
  }
  std::vector<const ReceptiveField*> ptrs;
  for (auto& c : copies) ptrs.push_back(&c);
  field = pack_lane_field(ptrs);
}
void update_lane_field_pair(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x, const double* y,
                            double w_a, LaneField& field_a, double w_b, LaneField& field_b, LaneScratch& scratch_a,
                            LaneScratch& scratch_b) {
  update_lane_field(params, trust_n_data, x, y, w_a, field_a, scratch_a);
  update_lane_field(params, trust_n_data, x, y, w_b, field_b, scratch_b);
}
}
