// The packed job configuration (engine/experiment/packed_job_config.hpp): every key set to a
// value other than its default comes back bit for bit (compared field by field through the key
// table, typed, not through the packing's own bytes), a default configuration packs to nothing,
// and the jobs of a sweep share the file contents they read.
#include "engine/experiment/packed_job_config.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace armfarm {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_bits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (!same_bits(a.data()[i], b.data()[i])) return false;
  }
  return true;
}

// Whether the two fields (of one key, in two configurations) hold the same value, typed.
bool same_value(const FieldRef& a, const FieldRef& b) {
  switch (a.kind) {
    case ValueKind::real: return same_bits(a.real(), b.real());
    case ValueKind::integer:
    case ValueKind::choice: return a.get_integer(a.field) == b.get_integer(b.field);
    case ValueKind::boolean: return a.boolean() == b.boolean();
    case ValueKind::text: return a.text() == b.text();
    case ValueKind::real_list:
    case ValueKind::real_or_list: return same_bits(Eigen::MatrixXd(a.vector()), Eigen::MatrixXd(b.vector()));
    case ValueKind::point: return same_bits(Eigen::MatrixXd(a.point()), Eigen::MatrixXd(b.point()));
    case ValueKind::integer_list: return a.integers() == b.integers();
    case ValueKind::name_list: return a.texts() == b.texts();
    case ValueKind::real_matrix: return same_bits(a.matrix(), b.matrix());
    case ValueKind::integer_or_auto: return a.optional_integer() == b.optional_integer();
    case ValueKind::real_or_auto:
      return a.optional_real().has_value() == b.optional_real().has_value() &&
             (!a.optional_real() || same_bits(*a.optional_real(), *b.optional_real()));
    case ValueKind::point_or_auto:
      return a.optional_point().has_value() == b.optional_point().has_value() &&
             (!a.optional_point() || same_bits(Eigen::MatrixXd(*a.optional_point()), Eigen::MatrixXd(*b.optional_point())));
  }
  return false;
}

// Sets the field to a value its default does not have (`k` varies it between keys).
void change_value(const FieldRef& f, int k) {
  const double x = 0.125 * (k + 1);
  switch (f.kind) {
    case ValueKind::real: f.real() = f.real() == x ? -x : x; return;
    case ValueKind::integer: f.set_integer(f.field, f.get_integer(f.field) + 1 + k); return;
    case ValueKind::choice: {
      const long long now = f.get_integer(f.field);
      for (const EnumName& name : *f.choices) {
        if (name.value != now) {
          f.set_integer(f.field, name.value);
          return;
        }
      }
      return;
    }
    case ValueKind::boolean: f.boolean() = !f.boolean(); return;
    case ValueKind::text: f.text() += "changed " + std::to_string(k); return;
    case ValueKind::real_list:
    case ValueKind::real_or_list: f.vector() = Eigen::Vector3d(x, -x, 1e-300); return;
    case ValueKind::point: f.point() += Eigen::Vector3d(x, 2 * x, -x); return;
    case ValueKind::integer_list: f.integers() = {k, 2, 3}; return;
    case ValueKind::name_list: f.texts() = {"a name " + std::to_string(k)}; return;
    case ValueKind::real_matrix: {
      Eigen::MatrixXd m(2, 3);
      m << x, 1, 2, 3, 4, -0.0;
      f.matrix() = m;
      return;
    }
    case ValueKind::integer_or_auto:
      f.optional_integer() = f.optional_integer() ? std::nullopt : std::optional<int>(k + 2);
      return;
    case ValueKind::real_or_auto:
      f.optional_real() = f.optional_real() ? std::nullopt : std::optional<double>(x);
      return;
    case ValueKind::point_or_auto:
      f.optional_point() = f.optional_point() ? std::nullopt : std::optional<Eigen::Vector3d>(Eigen::Vector3d(x, 0, -x));
      return;
  }
}

TEST(PackedJobConfig, EveryChangedKeyComesBackBitForBit) {
  const std::vector<JobConfigKey>& keys = job_config_keys();
  JobConfig changed;
  for (std::size_t i = 0; i < keys.size(); ++i) change_value(keys[i].field(changed), static_cast<int>(i));
  JobConfig defaults;
  std::size_t differing = 0;
  for (const JobConfigKey& key : keys) differing += same_value(key.field(changed), key.field(defaults)) ? 0 : 1;
  EXPECT_EQ(differing, keys.size());  // the test changes every key
  const std::string packed = pack_job_config_keys(changed);
  JobConfig back = unpack_job_config_keys(packed);
  for (const JobConfigKey& key : keys) EXPECT_TRUE(same_value(key.field(back), key.field(changed))) << key.path;
  // A key left at its default costs nothing; one changed key, its index, length and value.
  EXPECT_EQ(pack_job_config_keys(defaults), "");
  JobConfig one;
  one.control.gain_scale = 0.3;
  EXPECT_EQ(pack_job_config_keys(one).size(), 4u + 4u + sizeof(double));
  EXPECT_EQ(unpack_job_config_keys(pack_job_config_keys(one)).control.gain_scale, 0.3);
  // Bytes it did not write are refused, not read past their end.
  EXPECT_THROW(unpack_job_config_keys(packed.substr(0, packed.size() - 1)), std::logic_error);
}

}  // namespace
}  // namespace armfarm
