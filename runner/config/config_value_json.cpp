#include "runner/config/config_value_json.hpp"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>

namespace armfarm {
namespace {

using nlohmann::json;

json make_vector_json(const Eigen::Ref<const Eigen::VectorXd>& values) {
  json out = json::array();
  for (Eigen::Index i = 0; i < values.size(); ++i) out.push_back(values[i]);
  return out;
}

std::string show(const json& value) {
  std::string text = value.dump();
  return text.size() > 40 ? text.substr(0, 37) + "..." : text;
}

bool is_integral(const json& value) {
  if (value.is_number_integer()) return true;
  if (!value.is_number_float()) return false;
  const double x = value.get<double>();
  return std::isfinite(x) && x == std::floor(x) && std::fabs(x) < 9.0e15;
}

long long get_integral(const json& value) {
  if (value.is_number_unsigned()) return static_cast<long long>(value.get<unsigned long long>());
  if (value.is_number_integer()) return value.get<long long>();
  return static_cast<long long>(value.get<double>());
}

/// A number or a list of numbers → vector; "" or the problem.
std::string read_vector(const json& value, Eigen::VectorXd& out, std::string& suffix) {
  if (value.is_number()) {
    out = Eigen::VectorXd::Constant(1, value.get<double>());
    return "";
  }
  if (!value.is_array()) return "expected a number or a list of numbers, got " + show(value);
  Eigen::VectorXd result(static_cast<Eigen::Index>(value.size()));
  for (std::size_t i = 0; i < value.size(); ++i) {
    if (!value[i].is_number()) {
      suffix = "[" + std::to_string(i) + "]";
      return "expected a number, got " + show(value[i]);
    }
    result[static_cast<Eigen::Index>(i)] = value[i].get<double>();
  }
  out = result;
  return "";
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

}  // namespace

json make_field_json(const FieldRef& field) {
  switch (field.kind) {
    case ValueKind::real: return field.real();
    case ValueKind::integer: return field.get_integer(field.field);
    case ValueKind::boolean: return field.boolean();
    case ValueKind::text: return field.text();
    case ValueKind::choice: return find_enum_name(*field.choices, static_cast<int>(field.get_integer(field.field)));
    case ValueKind::real_list: return make_vector_json(field.vector());
    case ValueKind::real_or_list:
      return field.vector().size() == 1 ? json(field.vector()[0]) : make_vector_json(field.vector());
    case ValueKind::point: return make_vector_json(field.point());
    case ValueKind::integer_list: return json(field.integers());
    case ValueKind::name_list: return json(field.texts());
    case ValueKind::integer_or_auto:
      return field.optional_integer() ? json(*field.optional_integer()) : json(kAutoValue);
    case ValueKind::real_or_auto:
      return field.optional_real() ? json(*field.optional_real()) : json(kAutoValue);
    case ValueKind::point_or_auto:
      return field.optional_point() ? make_vector_json(*field.optional_point()) : json(kAutoValue);
    case ValueKind::real_matrix: {
      const Eigen::MatrixXd& m = field.matrix();
      if (m.rows() == 1 && m.cols() == 1) return m(0, 0);
      if (m.cols() == 1) return make_vector_json(m.col(0));
      json rows = json::array();
      for (Eigen::Index i = 0; i < m.rows(); ++i) rows.push_back(make_vector_json(m.row(i).transpose()));
      return rows;
    }
  }
  return nullptr;
}

namespace {

// One reader per ValueKind: each stores `value` into the field and returns "" on success, else
// what is wrong; `suffix` receives the element of a list at fault.

std::string read_real(const json& value, const FieldRef& field) {
  if (!value.is_number()) return "expected a number, got " + show(value);
  field.real() = value.get<double>();
  return "";
}

std::string read_integer(const json& value, const FieldRef& field) {
  if (!is_integral(value)) return "expected an integer, got " + show(value);
  // Above 2^63 − 1 the value would wrap to a negative one (a seed of 2^63 was echoed as
  // −9223372036854775808): no key's range reaches that far.
  if (value.is_number_unsigned() && value.get<unsigned long long>() > static_cast<unsigned long long>(LLONG_MAX)) {
    return show(value) + " does not fit a 64-bit signed integer (every integer key's range ends below 2^63)";
  }
  // Negative values stored into unsigned fields wrap back to negative in get_integer, where
  // validate()'s range check refuses them.
  field.set_integer(field.field, get_integral(value));
  return "";
}

bool is_auto(const json& value) { return value.is_string() && value.get<std::string>() == kAutoValue; }

std::string read_integer_or_auto(const json& value, const FieldRef& field) {
  if (is_auto(value)) {
    field.optional_integer().reset();
    return "";
  }
  if (!is_integral(value) || std::fabs(static_cast<double>(get_integral(value))) > 1e9) {
    return std::string("expected an integer or \"") + kAutoValue + "\", got " + show(value);
  }
  field.optional_integer() = static_cast<int>(get_integral(value));
  return "";
}

std::string read_real_or_auto(const json& value, const FieldRef& field) {
  if (is_auto(value)) {
    field.optional_real().reset();
    return "";
  }
  if (!value.is_number()) return std::string("expected a number or \"") + kAutoValue + "\", got " + show(value);
  field.optional_real() = value.get<double>();
  return "";
}

std::string read_point_or_auto(const json& value, const FieldRef& field, std::string& suffix) {
  if (is_auto(value)) {
    field.optional_point().reset();
    return "";
  }
  Eigen::VectorXd v;
  const std::string problem = value.is_array() ? read_vector(value, v, suffix)
                                               : "expected [x, y, z] or \"" + std::string(kAutoValue) + "\", got " + show(value);
  if (!problem.empty()) return problem;
  if (v.size() != 3) return std::string("expected 3 numbers [x, y, z] or \"") + kAutoValue + "\", got " + show(value);
  field.optional_point() = Eigen::Vector3d(v);
  return "";
}

std::string read_boolean(const json& value, const FieldRef& field, const FieldReadOptions& options) {
  if (value.is_boolean()) {
    field.boolean() = value.get<bool>();
    return "";
  }
  if (options.flags_as_numbers && is_integral(value) && (get_integral(value) == 0 || get_integral(value) == 1)) {
    field.boolean() = get_integral(value) == 1;
    return "";
  }
  return std::string("expected true or false") + (options.flags_as_numbers ? " (or 0/1)" : "") + ", got " + show(value);
}

std::string read_text(const json& value, const FieldRef& field) {
  if (!value.is_string()) return "expected a string, got " + show(value);
  field.text() = value.get<std::string>();
  return "";
}

std::string read_choice(const json& value, const FieldRef& field, const FieldReadOptions& options) {
  int choice = 0;
  const std::string text = value.is_string() ? value.get<std::string>() : "";
  if (value.is_string() && find_enum_value(*field.choices, options.case_insensitive_names ? lower(text) : text, choice)) {
    field.set_integer(field.field, choice);
    return "";
  }
  return "must be one of " + make_enum_choice_text(*field.choices) + ", not " + show(value);
}

std::string read_point(const json& value, const FieldRef& field, std::string& suffix) {
  Eigen::VectorXd v;
  const std::string problem = read_vector(value, v, suffix);
  if (!problem.empty()) return problem;
  if (v.size() != 3) return "expected 3 numbers [x, y, z], got " + show(value);
  field.point() = v;
  return "";
}

std::string read_integer_list(const json& value, const FieldRef& field, std::string& suffix) {
  if (!value.is_array()) return "expected a list of integers, got " + show(value);
  std::vector<int> result;
  for (std::size_t i = 0; i < value.size(); ++i) {
    if (!is_integral(value[i]) || std::fabs(static_cast<double>(get_integral(value[i]))) > 1e9) {
      suffix = "[" + std::to_string(i) + "]";
      return "expected an integer, got " + show(value[i]);
    }
    result.push_back(static_cast<int>(get_integral(value[i])));
  }
  field.integers() = result;
  return "";
}

std::string read_name_list(const json& value, const FieldRef& field, std::string& suffix) {
  if (!value.is_array()) return "expected a list of names, got " + show(value);
  std::vector<std::string> result;
  for (std::size_t i = 0; i < value.size(); ++i) {
    if (!value[i].is_string()) {
      suffix = "[" + std::to_string(i) + "]";
      return "expected a name, got " + show(value[i]);
    }
    result.push_back(value[i].get<std::string>());
  }
  field.texts() = result;
  return "";
}

// A list of equally long lists of numbers → matrix.
std::string read_matrix_rows(const json& value, Eigen::MatrixXd& out, std::string& suffix) {
  Eigen::MatrixXd m(value.size(), value[0].size());
  for (std::size_t i = 0; i < value.size(); ++i) {
    if (!value[i].is_array() || value[i].size() != value[0].size()) {
      suffix = "[" + std::to_string(i) + "]";
      return "rows of different lengths";
    }
    for (std::size_t j = 0; j < value[i].size(); ++j) {
      if (!value[i][j].is_number()) {
        suffix = "[" + std::to_string(i) + "][" + std::to_string(j) + "]";
        return "expected a number, got " + show(value[i][j]);
      }
      m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = value[i][j].get<double>();
    }
  }
  out = m;
  return "";
}

// A number (1×1), a list (a column) or a list of lists (rows).
std::string read_matrix(const json& value, const FieldRef& field, std::string& suffix) {
  if (value.is_array() && !value.empty() && value[0].is_array()) return read_matrix_rows(value, field.matrix(), suffix);
  if (value.is_array() && value.empty()) return "expected a number, a list or a list of lists, got []";
  Eigen::VectorXd v;
  const std::string problem = read_vector(value, v, suffix);
  if (!problem.empty()) return "expected a number, a list or a list of lists, got " + show(value);
  field.matrix() = v;
  return "";
}

}  // namespace

std::string read_field_json(const json& value, const FieldRef& field, std::string& suffix, const FieldReadOptions& options) {
  suffix.clear();
  switch (field.kind) {
    case ValueKind::real: return read_real(value, field);
    case ValueKind::integer: return read_integer(value, field);
    case ValueKind::integer_or_auto: return read_integer_or_auto(value, field);
    case ValueKind::real_or_auto: return read_real_or_auto(value, field);
    case ValueKind::point_or_auto: return read_point_or_auto(value, field, suffix);
    case ValueKind::boolean: return read_boolean(value, field, options);
    case ValueKind::text: return read_text(value, field);
    case ValueKind::choice: return read_choice(value, field, options);
    case ValueKind::real_list:
    case ValueKind::real_or_list: return read_vector(value, field.vector(), suffix);
    case ValueKind::point: return read_point(value, field, suffix);
    case ValueKind::integer_list: return read_integer_list(value, field, suffix);
    case ValueKind::name_list: return read_name_list(value, field, suffix);
    case ValueKind::real_matrix: return read_matrix(value, field, suffix);
  }
  return "unsupported field";
}

}  // namespace armfarm
