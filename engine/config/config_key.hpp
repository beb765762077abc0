#pragma once
// Key tables of configuration structs: plain data naming each field's key, unit, allowed range
// and doc line, and a typed reference to the field. Every component's *_config.hpp declares one
// table per struct beside the struct (whose member initialisers stay the only copy of each
// default); JobConfig's table (engine/experiment/job_config.hpp) concatenates them under their
// dotted prefixes. The JSON reader and writer (runner/config/), the single validation
// (engine/experiment/job_config_validation.hpp), the error messages and the documentation check
// are all driven by these tables, so a key, a range and an enum name are each spelled once.
//
// No JSON here: the engine knows nothing of file formats.
#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

/// One spelling of one enumerator: the name users write, its value, a doc line.
struct EnumName {
  const char* name;
  int value;
  const char* doc;
};
/// All spellings of one enum, in declaration order. Defined once per enum, beside the enum.
using EnumNames = std::vector<EnumName>;

/// "\"a\", \"b\" or \"c\"" for messages.
std::string make_enum_choice_text(const EnumNames& names);
/// The spelling of `value`; "?" when the table lacks it (a programming error caught by tests).
const char* find_enum_name(const EnumNames& names, int value);
/// The value spelled `name`; false when no enumerator has that name.
bool find_enum_value(const EnumNames& names, const std::string& name, int& value);

/// What shape of value a field holds (and so how it is written and read).
enum class ValueKind {
  real,          ///< double
  integer,       ///< an integral field (int, std::size_t, std::uint64_t) read through get/set_integer
  boolean,       ///< bool
  text,          ///< std::string
  choice,        ///< an enum, spelled by `choices`, read through get/set_integer
  real_list,     ///< Eigen::VectorXd, written as a list (empty = the field's stated rule)
  real_or_list,  ///< Eigen::VectorXd, written as a number when it has one element
  point,         ///< Eigen::Vector3d, [x, y, z]
  integer_list,  ///< std::vector<int>
  name_list,     ///< std::vector<std::string>, each one of `names()`
  real_matrix,   ///< Eigen::MatrixXd: a number (1×1), a list (n×1) or a list of lists (n×n)
  integer_or_auto,  ///< std::optional<int>: an integer, or kAutoValue (empty: armfarm chooses, as the key's doc says)
  real_or_auto,     ///< std::optional<double>: a number, or kAutoValue (empty)
  point_or_auto,    ///< std::optional<Eigen::Vector3d>: [x, y, z], or kAutoValue (empty)
};

/// How a user writes "armfarm chooses" for an integer_or_auto or real_or_auto key.
inline constexpr const char* kAutoValue = "auto";

/// Allowed values of a number (of each element of a list): [min, max], either end open.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;
  bool max_open = false;

  bool contains(double value) const;
  /// "(0, 0.1]", "[1, 10000]", ">= 0", "> 0", "any".
  std::string describe() const;
};
/// [min, max]; (min, max]; [min, max); (min, max).
inline Range closed(double min, double max) { return {min, max, false, false}; }
inline Range left_open(double min, double max) { return {min, max, true, false}; }
inline Range right_open(double min, double max) { return {min, max, false, true}; }
inline Range open(double min, double max) { return {min, max, true, true}; }

/// How many elements a list field may have (checked by validate() with the model's facts).
enum class ListSize {
  any,            ///< not a list, or no rule
  per_joint,      ///< 0 (the stated rule), 1 (all joints) or one per active joint
  joint_numbers,  ///< active_joints: distinct 1-based movable joint numbers
  lwpr_inputs,    ///< 1 or 3 × active joints (q, q̇, q̈)
  lwpr_outputs,   ///< 1 or one per active joint
  movable_joints, ///< 0 (the stated rule) or one per movable joint of the model, active or locked
};

/// A typed reference to one field of one struct instance. `field` points at the member; its
/// C++ type follows from `kind` (see ValueKind). Integral and enum fields are read and written
/// through get_integer/set_integer so that one kind serves int, size_t, uint64 and every enum.
struct FieldRef {
  ValueKind kind = ValueKind::real;
  void* field = nullptr;
  long long (*get_integer)(const void* field) = nullptr;
  void (*set_integer)(void* field, long long value) = nullptr;
  const EnumNames* choices = nullptr;                  ///< choice
  const std::vector<std::string>& (*names)() = nullptr;  ///< name_list: the allowed names

  double& real() const { return *static_cast<double*>(field); }
  bool& boolean() const { return *static_cast<bool*>(field); }
  std::string& text() const { return *static_cast<std::string*>(field); }
  Eigen::VectorXd& vector() const { return *static_cast<Eigen::VectorXd*>(field); }
  Eigen::Vector3d& point() const { return *static_cast<Eigen::Vector3d*>(field); }
  Eigen::MatrixXd& matrix() const { return *static_cast<Eigen::MatrixXd*>(field); }
  std::vector<int>& integers() const { return *static_cast<std::vector<int>*>(field); }
  std::vector<std::string>& texts() const { return *static_cast<std::vector<std::string>*>(field); }
  std::optional<int>& optional_integer() const { return *static_cast<std::optional<int>*>(field); }
  std::optional<double>& optional_real() const { return *static_cast<std::optional<double>*>(field); }
  std::optional<Eigen::Vector3d>& optional_point() const { return *static_cast<std::optional<Eigen::Vector3d>*>(field); }
};

FieldRef make_field(double& value);
FieldRef make_field(bool& value);
FieldRef make_field(std::string& value);
FieldRef make_field(Eigen::Vector3d& value);
FieldRef make_field(std::vector<int>& value);
FieldRef make_field(Eigen::MatrixXd& value);
FieldRef make_field(std::optional<int>& value);     ///< integer_or_auto
FieldRef make_field(std::optional<double>& value);  ///< real_or_auto
FieldRef make_field(std::optional<Eigen::Vector3d>& value);  ///< point_or_auto
/// kind real_list or real_or_list.
FieldRef make_field(Eigen::VectorXd& value, ValueKind kind = ValueKind::real_list);
FieldRef make_field(std::vector<std::string>& value, const std::vector<std::string>& (*names)());

template <typename Integral>
FieldRef make_integer_field(Integral& value) {
  FieldRef ref;
  ref.kind = ValueKind::integer;
  ref.field = &value;
  ref.get_integer = [](const void* f) { return static_cast<long long>(*static_cast<const Integral*>(f)); };
  ref.set_integer = [](void* f, long long v) { *static_cast<Integral*>(f) = static_cast<Integral>(v); };
  return ref;
}

template <typename Enum>
FieldRef make_choice_field(Enum& value, const EnumNames& choices) {
  FieldRef ref;
  ref.kind = ValueKind::choice;
  ref.field = &value;
  ref.choices = &choices;
  ref.get_integer = [](const void* f) { return static_cast<long long>(*static_cast<const Enum*>(f)); };
  ref.set_integer = [](void* f, long long v) { *static_cast<Enum*>(f) = static_cast<Enum>(v); };
  return ref;
}

/// One row of a struct's key table.
template <typename Struct>
struct ConfigKey {
  const char* name;   ///< key within the struct ("bandwidth"; "payload.mass" for a nested plain struct)
  const char* unit;   ///< SI unit, "" for dimensionless, flags, names
  Range range;        ///< numbers: of the value, or of each element (integers: closed, integral)
  ListSize size;      ///< list fields: how many elements
  const char* doc;    ///< one line: what it is, and the rule an empty list stands for
  FieldRef (*field)(Struct& config);
};

}  // namespace armfarm
