#include "engine/config/config_key.hpp"

#include "base/number_format.hpp"

#include <cmath>

namespace armfarm {

std::string make_enum_choice_text(const EnumNames& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) text += i + 1 == names.size() ? " or " : ", ";
    text += std::string("\"") + names[i].name + "\"";
  }
  return text;
}

const char* find_enum_name(const EnumNames& names, int value) {
  for (const EnumName& name : names) {
    if (name.value == value) return name.name;
  }
  return "?";
}

bool find_enum_value(const EnumNames& names, const std::string& text, int& value) {
  for (const EnumName& name : names) {
    if (text == name.name) {
      value = name.value;
      return true;
    }
  }
  return false;
}

bool Range::contains(double value) const {
  if (std::isnan(value)) return false;
  if (min_open ? !(value > min) : !(value >= min)) return false;
  if (max_open ? !(value < max) : !(value <= max)) return false;
  return true;
}

std::string Range::describe() const {
  const bool has_min = std::isfinite(min);
  const bool has_max = std::isfinite(max);
  if (has_min && has_max) {
    return std::string(min_open ? "(" : "[") + format_number(min) + ", " + format_number(max) + (max_open ? ")" : "]");
  }
  if (has_min) return std::string(min_open ? "> " : ">= ") + format_number(min);
  if (has_max) return std::string(max_open ? "< " : "<= ") + format_number(max);
  return "any";
}

FieldRef make_field(double& value) { return FieldRef{ValueKind::real, &value}; }
FieldRef make_field(bool& value) { return FieldRef{ValueKind::boolean, &value}; }
FieldRef make_field(std::string& value) { return FieldRef{ValueKind::text, &value}; }
FieldRef make_field(Eigen::Vector3d& value) { return FieldRef{ValueKind::point, &value}; }
FieldRef make_field(std::vector<int>& value) { return FieldRef{ValueKind::integer_list, &value}; }
FieldRef make_field(Eigen::MatrixXd& value) { return FieldRef{ValueKind::real_matrix, &value}; }
FieldRef make_field(std::optional<int>& value) { return FieldRef{ValueKind::integer_or_auto, &value}; }
FieldRef make_field(std::optional<double>& value) { return FieldRef{ValueKind::real_or_auto, &value}; }
FieldRef make_field(std::optional<Eigen::Vector3d>& value) { return FieldRef{ValueKind::point_or_auto, &value}; }
FieldRef make_field(Eigen::VectorXd& value, ValueKind kind) { return FieldRef{kind, &value}; }
FieldRef make_field(std::vector<std::string>& value, const std::vector<std::string>& (*names)()) {
  FieldRef ref{ValueKind::name_list, &value};
  ref.names = names;
  return ref;
}

}  // namespace armfarm
