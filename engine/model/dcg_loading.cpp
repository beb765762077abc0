// The thesis's DCG tag format (appendix B, example in appendix C) → ArmModel.
//
//   <DCGraph>
//   B <body> <transforms> tag(...) ... ;        a body; its transforms give its world pose
//   J <parent>-<child> <before || after> ... ;   a joint between two bodies
//   </DCGraph>
//
// Conventions (models/README.md): transforms compose left to right, each in the frame the
// previous ones produced; `t(x y z)` translates (m), `d(angle ax ay az)` rotates by degrees
// about an axis. Before `||`: the joint frame in the parent body frame; after: the child body
// frame in the joint frame. Hinges turn about the joint frame's x axis (thesis figure 5.3),
// sliders move along it. `#` starts a comment. A synthetic root link "world" carries every
// `fix` body through a fixed joint.
#include "engine/io/input_file.hpp"
#include "engine/io/number_text.hpp"
#include "engine/model/mass_properties.hpp"
#include "engine/model/model_file.hpp"
#include "engine/model/model_loaders.hpp"
#include "engine/model/model_loading.hpp"
#include "engine/model/model_validation.hpp"
#include "engine/model/start_posture.hpp"
#include "engine/model/triangle_mesh.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <utility>

namespace armfarm {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;

struct Tag {
  std::string name;
  std::vector<double> numbers;  // tag(...)
  std::string text;             // tag[...]
  bool has_numbers = false;
  bool has_text = false;
  int line = 0;
};

struct Entry {
  char kind = 'B';  // 'B' body or 'J' joint
  std::string name;
  int line = 0;
  Eigen::Isometry3d before = Eigen::Isometry3d::Identity();  // body: its pose; joint: joint in parent
  Eigen::Isometry3d after = Eigen::Isometry3d::Identity();   // joint: child body in joint frame
  bool has_transforms = false;
  std::map<std::string, Tag> tags;
};

class DcgParser {
 public:
  DcgParser(std::string path, std::string text) : path_(std::move(path)), text_(std::move(text)) {}

  std::vector<Entry> parse() {
    skip_space();
    if (!consume("<DCGraph>")) fail(line_, "expected <DCGraph> at the start of the file");
    std::vector<Entry> entries;
    while (true) {
      skip_space();
      if (at_end()) fail(line_, "missing </DCGraph> at the end of the file");
      if (consume("</DCGraph>")) break;
      entries.push_back(parse_entry());
    }
    skip_space();
    if (!at_end()) fail(line_, "text after </DCGraph>");
    return entries;
  }

  [[noreturn]] void fail(int line, const std::string& what) const {
    throw ModelError(path_ + ":" + std::to_string(line) + ": " + what);
  }

 private:
  bool at_end() const { return pos_ >= text_.size(); }
  char peek() const { return at_end() ? '\0' : text_[pos_]; }
  void advance() {
    if (text_[pos_] == '\n') ++line_;
    ++pos_;
  }
  bool consume(const std::string& literal) {
    if (text_.compare(pos_, literal.size(), literal) != 0) return false;
    for (std::size_t k = 0; k < literal.size(); ++k) advance();
    return true;
  }
  void skip_space() {
    while (!at_end()) {
      if (std::isspace(static_cast<unsigned char>(peek()))) {
        advance();
      } else if (peek() == '#') {
        while (!at_end() && peek() != '\n') advance();
      } else {
        break;
      }
    }
  }
  std::string read_word() {  // a name: anything up to space or a delimiter
    std::string word;
    while (!at_end() && !std::isspace(static_cast<unsigned char>(peek())) && std::string("<>;()[]#").find(peek()) == std::string::npos) {
      word += peek();
      advance();
    }
    return word;
  }
  std::string read_identifier() {
    std::string word;
    while (!at_end() && (std::isalpha(static_cast<unsigned char>(peek())) || peek() == '_')) {
      word += peek();
      advance();
    }
    return word;
  }
  std::string read_until(char close, const std::string& what) {
    const int start_line = line_;
    std::string content;
    while (!at_end() && peek() != close) {
      if (peek() == ';' || peek() == '>') break;
      content += peek();
      advance();
    }
    if (peek() != close) fail(start_line, what + ": missing '" + std::string(1, close) + "'");
    advance();
    return content;
  }
  std::vector<double> parse_numbers(const std::string& content, const std::string& tag, int line) const {
    std::string cleaned = content;
    for (char& c : cleaned) {
      if (c == ',') c = ' ';
    }
    std::istringstream tokens(cleaned);
    std::vector<double> values;
    std::string token;
    while (tokens >> token) {
      // All of the token (an embedded NUL or control character is not a number), finite.
      const std::optional<double> value = parse_finite_number(token);
      if (!value) {
        fail(line, "tag " + tag + ": value " + std::to_string(values.size() + 1) + make_bad_number_ending(token));
      }
      values.push_back(*value);
    }
    return values;
  }

  Eigen::Isometry3d parse_transform(const std::string& name, int line) {
    if (peek() != '(') fail(line, "transform '" + name + "' needs '(' (expected t(x y z) or d(angle ax ay az))");
    advance();
    const std::vector<double> v = parse_numbers(read_until(')', "transform " + name), name, line);
    Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
    if (name == "t") {
      if (v.size() != 3) fail(line, "t(...) needs three numbers (x y z in metres), got " + std::to_string(v.size()));
      transform.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
    } else if (name == "d") {
      if (v.size() != 4) fail(line, "d(...) needs four numbers (angle in degrees, then the axis), got " + std::to_string(v.size()));
      const Eigen::Vector3d axis(v[1], v[2], v[3]);
      if (axis.norm() < 1e-12) fail(line, "d(...) has a zero rotation axis");
      transform.linear() = Eigen::AngleAxisd(v[0] * kDegree, axis.normalized()).toRotationMatrix();
    } else {
      fail(line, "unknown transform '" + name + "' (expected t(x y z) or d(angle ax ay az))");
    }
    return transform;
  }

  void parse_group(Entry& entry) {
    advance();  // '<'
    bool after_bar = false;
    while (true) {
      skip_space();
      if (at_end()) fail(entry.line, "unterminated transform group '<...>'");
      if (peek() == '>') {
        advance();
        return;
      }
      if (consume("||")) {
        if (entry.kind != 'J') fail(line_, "'||' is only meaningful in a joint's transforms");
        if (after_bar) fail(line_, "second '||' in one transform group");
        after_bar = true;
        continue;
      }
      const int line = line_;
      const std::string name = read_identifier();
      if (name.empty()) fail(line, std::string("unexpected '") + peek() + "' in a transform group");
      const Eigen::Isometry3d transform = parse_transform(name, line);
      entry.has_transforms = true;
      Eigen::Isometry3d& target = after_bar ? entry.after : entry.before;
      target = target * transform;
    }
  }

  Entry parse_entry() {
    Entry entry;
    entry.line = line_;
    const std::string kind = read_word();
    if (kind != "B" && kind != "J") {
      fail(entry.line, "unknown entry '" + kind + "' (expected B <body> or J <parent>-<child>)");
    }
    entry.kind = kind[0];
    skip_space();
    entry.name = read_word();
    if (entry.name.empty()) fail(entry.line, std::string(kind == "B" ? "body" : "joint") + " without a name");
    while (true) {
      skip_space();
      if (at_end()) fail(entry.line, "entry '" + entry.name + "' is not terminated by ';'");
      if (peek() == ';') {
        advance();
        return entry;
      }
      if (peek() == '<') {
        if (!entry.tags.empty() || entry.has_transforms) fail(line_, "the transform group must follow the name");
        parse_group(entry);
        continue;
      }
      Tag tag;
      tag.line = line_;
      tag.name = read_identifier();
      if (tag.name.empty()) fail(line_, std::string("unexpected '") + peek() + "' in entry '" + entry.name + "'");
      if (peek() == '(') {
        advance();
        tag.numbers = parse_numbers(read_until(')', "tag " + tag.name), tag.name, tag.line);
        tag.has_numbers = true;
      } else if (peek() == '[') {
        advance();
        tag.text = read_until(']', "tag " + tag.name);
        tag.has_text = true;
      }
      if ((tag.name == "B" || tag.name == "J") && !tag.has_numbers && !tag.has_text) {
        fail(tag.line, "entry '" + entry.name + "' (line " + std::to_string(entry.line) + ") is missing its ';'");
      }
      if (tag.name == "l") tag.name = "I";  // appendix C's listing writes the inertia tag I as l
      if (!entry.tags.emplace(tag.name, tag).second) fail(tag.line, "tag " + tag.name + " given twice in '" + entry.name + "'");
    }
  }

  std::string path_;
  std::string text_;
  std::size_t pos_ = 0;
  int line_ = 1;
};

// Tag signatures: the counts of numbers a tag accepts (empty: a [text] tag; {0}: a flag).
const std::map<std::string, std::set<int>>& body_tags() {
  static const std::map<std::string, std::set<int>> tags = {
      {"o", {1}}, {"f", {}}, {"s", {1, 2, 3, 4}}, {"m", {1}}, {"c", {3}}, {"fix", {0}},
      {"I", {3, 9}}, {"X", {3}}, {"w", {1}}, {"ee", {3}}};
  return tags;
}
const std::map<std::string, std::set<int>>& joint_tags() {
  static const std::map<std::string, std::set<int>> tags = {
      {"a", {1}}, {"p", {2}}, {"j", {1}}, {"effort", {1}}, {"vel", {1}}, {"damp", {1}}, {"fric", {1}}, {"arm", {1}}};
  return tags;
}

std::string tag_list(const std::map<std::string, std::set<int>>& tags) {
  std::string list;
  for (const auto& [name, counts] : tags) list += (list.empty() ? "" : " ") + name;
  return list;
}

class DcgBuilder {
 public:
  DcgBuilder(std::string path, const DcgParser& parser) : path_(std::move(path)), parser_(parser) {}

  ArmModel build(const std::vector<Entry>& entries) {
    model_.source_file = path_;
    model_.input_files.insert(model_.input_files.begin(), path_);
    const std::size_t slash = path_.find_last_of('/');
    directory_ = slash == std::string::npos ? "" : path_.substr(0, slash + 1);
    std::string stem = path_.substr(slash == std::string::npos ? 0 : slash + 1);
    model_.name = stem.substr(0, stem.find_last_of('.'));

    Link world;
    world.name = "world";
    world.fixed_to_world = true;
    model_.links.push_back(world);
    lines_.links["world"] = 1;
    link_index_["world"] = 0;

    for (const char kind : {'B', 'J'}) {
      const auto count = std::count_if(entries.begin(), entries.end(), [&](const Entry& e) { return e.kind == kind; });
      if (count > kMaxModelLinks) {
        throw ModelError(path_ + ": " + std::to_string(count) + (kind == 'B' ? " bodies" : " joints") + ", over the cap of " +
                         std::to_string(kMaxModelLinks) + " per arm model");
      }
    }
    for (const Entry& e : entries) {
      if (e.kind == 'B') add_body(e);
    }
    for (const Entry& e : entries) {
      if (e.kind == 'J') read_joint(e);
    }
    order_joints();  // the end effector: ee(...) when a body has it, else choose_end_effector (end_effector.hpp)
    validate_arm_model(model_, lines_);
    return model_;
  }

 private:
  [[noreturn]] void fail(int line, const std::string& what) const { parser_.fail(line, what); }

  void check_tags(const Entry& e, const std::map<std::string, std::set<int>>& allowed) const {
    const std::string what = e.kind == 'B' ? "body '" + e.name + "'" : "joint '" + e.name + "'";
    for (const auto& [name, tag] : e.tags) {
      const auto it = allowed.find(name);
      if (it == allowed.end()) {
        fail(tag.line, what + ": unknown tag '" + name + "' (allowed: " + tag_list(allowed) + ")");
      }
      const bool wants_text = it->second.empty();
      if (wants_text != tag.has_text) fail(tag.line, what + ": tag " + name + (wants_text ? " needs [text]" : " takes no [text]"));
      if (!wants_text) {
        const int count = tag.has_numbers ? static_cast<int>(tag.numbers.size()) : 0;
        if (it->second.count(count) == 0) {
          fail(tag.line, what + ": tag " + name + " has " + std::to_string(count) + " numbers (wrong count)");
        }
      }
    }
  }

  static const Tag* find(const Entry& e, const std::string& name) {
    const auto it = e.tags.find(name);
    return it == e.tags.end() ? nullptr : &it->second;
  }

  /// Body entry `e` as the next link: its shape, its mass properties (from the shape at the
  /// density m(...), or the mass w(...), overridden by X(...) and I(...)), its end effector ee(...).
  void add_body(const Entry& e) {
    check_tags(e, body_tags());
    const std::string what = "body '" + e.name + "'";
    register_body(e);
    Link link;
    link.name = e.name;
    link.fixed_to_world = find(e, "fix") != nullptr;
    LinkShape shape;
    const Inertial unit = read_shape(e, what, shape);
    link.inertial = calc_body_inertial(e, what, unit, link.fixed_to_world);
    link.shapes.push_back(shape);
    read_end_effector(e, what, static_cast<int>(model_.links.size()));
    model_.links.push_back(link);
  }

  /// The body's name, unique and not "world", with its line and entry (joints refer to it).
  void register_body(const Entry& e) {
    if (e.name == "world") fail(e.line, "the body name 'world' is reserved for the synthetic root");
    if (!link_index_.emplace(e.name, static_cast<int>(model_.links.size())).second) {
      fail(e.line, "duplicate body name '" + e.name + "'");
    }
    lines_.links[e.name] = e.line;
    body_entries_[e.name] = e;
  }

  /// The body's shape from o(type), s(...) or f[file.obj], and c(r g b); returns the shape's
  /// mass properties at density 1 (mass = volume in m³, inertia in m⁵).
  Inertial read_shape(const Entry& e, const std::string& what, LinkShape& shape) {
    const Tag* type = find(e, "o");
    if (type == nullptr) fail(e.line, what + ": no object type o(0 sphere | 1 box | 2 capped cylinder | 3 trimesh)");
    const double code = type->numbers[0];
    if (const Tag* c = find(e, "c")) shape.colour = Eigen::Vector3d(c->numbers[0], c->numbers[1], c->numbers[2]);
    const Tag* size = find(e, "s");
    const Tag* file = find(e, "f");
    if (code != 3 && file != nullptr) fail(file->line, what + ": f[...] names a mesh but the body is not a trimesh o(3)");
    if (code == 3 && size != nullptr) fail(size->line, what + ": s(...) has no effect on a trimesh o(3); remove it");
    if (code != 3 && size == nullptr) fail(e.line, what + ": no size s(...)");
    if (code == 0 || code == 1 || code == 2) return read_primitive(code, what, *size, shape);
    if (code == 3) return read_mesh(e, what, file, shape);
    fail(type->line, what + ": unknown object type o(" + std::to_string(code) + ") (0 sphere, 1 box, 2 capped cylinder, 3 trimesh)");
  }

  /// A sphere o(0), box o(1) or capped cylinder o(2) from its sizes s(...) (m, positive; also the
  /// thesis's four-number forms); returns its mass properties at density 1.
  Inertial read_primitive(double code, const std::string& what, const Tag& size, LinkShape& shape) const {
    const auto size_at = [&](int index) {
      const double value = size.numbers[index];
      if (!(value > 0.0)) fail(size.line, what + ": sizes must be positive (s(...) has " + std::to_string(value) + ")");
      return value;
    };
    const int n = static_cast<int>(size.numbers.size());
    if (code == 0) {  // sphere: s(r), or MT's s(sx sy sz r)
      if (n != 1 && n != 4) fail(size.line, what + ": a sphere takes s(radius) or s(sx sy sz radius)");
      const double r = size_at(n == 1 ? 0 : 3);
      shape.kind = LinkShape::Kind::sphere;
      shape.size = Eigen::Vector3d(r, 0, 0);
      return calc_sphere_inertial(1.0, r);
    }
    if (code == 1) {  // box: s(sx sy sz) or s(sx sy sz r)
      if (n != 3 && n != 4) fail(size.line, what + ": a box takes s(sx sy sz)");
      shape.kind = LinkShape::Kind::box;
      shape.size = Eigen::Vector3d(size_at(0), size_at(1), size_at(2));
      return calc_box_inertial(1.0, shape.size);
    }
    // capped cylinder: s(r length) or s(sx sy length r)
    if (n != 2 && n != 4) fail(size.line, what + ": a capped cylinder takes s(radius length) or s(sx sy length radius)");
    const double r = size_at(n == 2 ? 0 : 3);
    const double length = size_at(n == 2 ? 1 : 2);
    shape.kind = LinkShape::Kind::capped_cylinder;
    shape.size = Eigen::Vector3d(r, length, 0);
    return calc_capped_cylinder_inertial(1.0, r, length);
  }

  /// A trimesh o(3) from f[file.obj], a path inside the model file's folder (added to the
  /// model's input files once); returns the closed mesh's mass properties at density 1.
  Inertial read_mesh(const Entry& e, const std::string& what, const Tag* file, LinkShape& shape) {
    if (file == nullptr) fail(e.line, what + ": a trimesh o(3) needs f[file.obj]");
    shape.kind = LinkShape::Kind::mesh;
    try {
      shape.mesh_file = resolve_confined_path(directory_, file->text);
      check_real_path_inside(directory_, shape.mesh_file, file->text);
    } catch (const InputFileError& error) {
      fail(file->line, what + ": f[...]: " + error.what());
    }
    if (mesh_files_.insert(shape.mesh_file).second) model_.input_files.push_back(shape.mesh_file);
    Inertial unit;
    try {
      const MeshMassProperties mesh = calc_mesh_mass_properties(load_obj_mesh(shape.mesh_file));
      unit = calc_mesh_inertial_for_mass(mesh, mesh.volume);
    } catch (const ModelError& error) {
      fail(file->line, what + ": " + error.what());
    }
    return unit;
  }

  /// The body's mass properties from the shape's at density 1 (`unit`): the mass w(kg), else the
  /// density m(kg/m³) times the volume, else 0 for a fixed body; the inertia scaled with the
  /// mass; then the centre of mass X(m) and the inertia I(kg·m², diagonal or 3×3 row-major)
  /// as given. A massless fixed body has no mass properties at all.
  Inertial calc_body_inertial(const Entry& e, const std::string& what, const Inertial& unit, bool fixed_to_world) const {
    const double volume = unit.mass;  // density 1
    const Tag* density = find(e, "m");
    const Tag* mass = find(e, "w");
    Inertial inertial = unit;
    if (mass != nullptr) {
      inertial.mass = mass->numbers[0];
    } else if (density != nullptr) {
      inertial.mass = density->numbers[0] * volume;
    } else if (fixed_to_world) {
      inertial.mass = 0.0;  // a fixed body needs no mass
    } else {
      fail(e.line, what + ": no density m(...) or mass w(...)");
    }
    inertial.inertia = unit.inertia * (inertial.mass / volume);
    if (const Tag* com = find(e, "X")) inertial.com = Eigen::Vector3d(com->numbers[0], com->numbers[1], com->numbers[2]);
    if (const Tag* inertia = find(e, "I")) {
      const std::vector<double>& v = inertia->numbers;
      inertial.inertia = v.size() == 3 ? Eigen::Matrix3d(Eigen::Vector3d(v[0], v[1], v[2]).asDiagonal())
                                       : Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(v.data());
    }
    if (fixed_to_world && inertial.mass == 0.0) inertial = Inertial{};
    return inertial;
  }

  /// ee(x y z): the end effector on link `link` at that offset (m, in the body frame); one per file.
  void read_end_effector(const Entry& e, const std::string& what, int link) {
    const Tag* ee = find(e, "ee");
    if (ee == nullptr) return;
    if (ee_line_ != 0) fail(ee->line, what + ": a second end effector ee(...) (the first is on line " + std::to_string(ee_line_) + ")");
    ee_line_ = ee->line;
    model_.end_effector.link = link;
    model_.end_effector.offset = Eigen::Vector3d(ee->numbers[0], ee->numbers[1], ee->numbers[2]);
  }

  /// Joint entry `e` between two bodies (named <parent>-<child>): its type, frames, limits and
  /// tags, checked against its child body, kept in file order for order_joints.
  void read_joint(const Entry& e) {
    check_tags(e, joint_tags());
    const std::string what = "joint '" + e.name + "'";
    const std::pair<std::string, std::string> bodies = split_joint_name(e, what);
    Joint joint;
    joint.name = e.name;
    joint.parent_link = link_index_.at(bodies.first);
    joint.child_link = link_index_.at(bodies.second);
    joint.origin = e.before;
    joint.child_offset = e.after;
    joint.axis = Eigen::Vector3d::UnitX();
    joint.effort_limit = std::numeric_limits<double>::infinity();
    joint.velocity_limit = std::numeric_limits<double>::infinity();
    joint.type = read_joint_type(e, what);
    read_joint_tags(e, what, joint);
    attach_joint(e, what, joint, body_entries_.at(bodies.second));
  }

  /// The joint's (parent, child) bodies: body names may contain '-', so exactly one split of
  /// the name at a '-' must name two defined bodies.
  std::pair<std::string, std::string> split_joint_name(const Entry& e, const std::string& what) const {
    std::vector<std::pair<std::string, std::string>> splits;
    for (std::size_t dash = e.name.find('-'); dash != std::string::npos; dash = e.name.find('-', dash + 1)) {
      const std::string parent = e.name.substr(0, dash);
      const std::string child = e.name.substr(dash + 1);
      if (body_entries_.count(parent) != 0 && body_entries_.count(child) != 0) splits.emplace_back(parent, child);
    }
    if (splits.size() != 1) {
      fail(e.line, what + ": the name must be <parent>-<child> of two defined bodies (" +
                       (splits.empty() ? "no such bodies" : "ambiguous") + ")");
    }
    return splits[0];
  }

  /// The joint type of j(code), ODE's numbering: 2 hinge (the default), 3 slider, 7 fixed; the
  /// ball, universal and hinge-2 joints (1, 5, 6) and others are refused. A hinge without p(...)
  /// becomes continuous in read_joint_tags.
  JointType read_joint_type(const Entry& e, const std::string& what) const {
    int code = 2;  // ODE's dJointTypeHinge
    if (const Tag* t = find(e, "j")) code = static_cast<int>(t->numbers[0]);
    const Tag* type_tag = find(e, "j");
    if (type_tag != nullptr && type_tag->numbers[0] != std::floor(type_tag->numbers[0])) {
      fail(type_tag->line, what + ": j(...) needs an integer joint type");
    }
    switch (code) {
      case 2: return JointType::revolute;
      case 3: return JointType::prismatic;
      case 7: return JointType::fixed;
      case 1: case 5: case 6:
        fail(type_tag->line, what + ": j(" + std::to_string(code) + ") (" + (code == 1 ? "ball" : code == 5 ? "universal" : "hinge-2") +
                                 ") is not supported: armfarm joints have one degree of freedom (j(2) hinge, j(3) slider, j(7) fixed)");
      default:
        fail(type_tag->line, what + ": unknown joint type j(" + std::to_string(code) + ") (j(2) hinge, j(3) slider, j(7) fixed)");
    }
  }

  /// The joint's tags, hinges in degrees and sliders in metres: limits p(lower upper) (a hinge
  /// without them is continuous, appendix B), start a(...), effort (N·m or N), vel (per second),
  /// damp, fric, arm (kg·m²). A fixed joint j(7) takes none of them.
  void read_joint_tags(const Entry& e, const std::string& what, Joint& joint) const {
    const bool angular = joint.type == JointType::revolute;
    const double unit = angular ? kDegree : 1.0;  // hinges in degrees, sliders in metres
    if (const Tag* t = find(e, "p")) {
      joint.has_position_limits = true;
      joint.lower = t->numbers[0] * unit;
      joint.upper = t->numbers[1] * unit;
    } else if (angular) {
      joint.type = JointType::continuous;  // appendix B: no p, no joint angle restrictions
    }
    if (const Tag* t = find(e, "a")) {
      joint.start_position = t->numbers[0] * unit;
      joint.start_position_from_file = true;
    } else {
      joint.start_position = calc_default_start_position(joint);
    }
    if (const Tag* t = find(e, "effort")) joint.effort_limit = t->numbers[0];
    if (const Tag* t = find(e, "vel")) joint.velocity_limit = t->numbers[0] * unit;
    if (const Tag* t = find(e, "damp")) joint.damping = t->numbers[0];
    if (const Tag* t = find(e, "fric")) joint.friction = t->numbers[0];
    if (const Tag* t = find(e, "arm")) joint.armature = t->numbers[0];
    if (joint.type == JointType::fixed) {
      for (const char* name : {"a", "p", "effort", "vel", "damp", "fric", "arm"}) {
        if (const Tag* t = find(e, name)) fail(t->line, what + ": tag " + name + " makes no sense on a fixed joint j(7)");
      }
    }
  }

  /// The joint as its child body's one parent: the child must be movable (not fix) and placed by
  /// the joint alone (an empty group <>). Records the joint's line and keeps it (file order).
  void attach_joint(const Entry& e, const std::string& what, const Joint& joint, const Entry& child) {
    if (model_.links[joint.child_link].fixed_to_world) {
      fail(e.line, what + ": its child '" + child.name + "' is fixed (fix); a fixed body cannot be moved by a joint");
    }
    if (child.has_transforms) {
      fail(child.line, "body '" + child.name + "': has its own transforms <...> but joint '" + e.name +
                           "' places it; leave the body's group empty <>");
    }
    if (const auto it = parent_joint_.find(joint.child_link); it != parent_joint_.end()) {
      fail(e.line, what + ": body '" + child.name + "' has several parents (also joint '" + joints_[it->second].name + "')");
    }
    parent_joint_[joint.child_link] = static_cast<int>(joints_.size());
    lines_.joints[e.name] = e.line;
    joints_.push_back(joint);
  }

  // Tree order (calc_tree_order): from the synthetic world, each fixed body in file order by
  // its weld, then depth first along the file's joints. Cycles and bodies hanging in the air
  // are reported here.
  void order_joints() {
    std::vector<Joint> candidates;  // the welds, then the file's joints
    for (int l = 1; l < static_cast<int>(model_.links.size()); ++l) {
      if (!model_.links[l].fixed_to_world) continue;
      Joint weld;
      weld.name = "world-" + model_.links[l].name;
      weld.type = JointType::fixed;
      weld.parent_link = 0;
      weld.child_link = l;
      weld.origin = body_entries_.at(model_.links[l].name).before;
      weld.effort_limit = std::numeric_limits<double>::infinity();
      weld.velocity_limit = std::numeric_limits<double>::infinity();
      lines_.joints[weld.name] = lines_.links[model_.links[l].name];
      candidates.push_back(weld);
    }
    if (candidates.empty()) fail(1, "no fixed body: anchor the arm with a body tagged fix");
    candidates.insert(candidates.end(), joints_.begin(), joints_.end());
    std::vector<TreeEdge> edges;
    for (const Joint& joint : candidates) edges.push_back({joint.parent_link, joint.child_link});
    std::set<int> placed{0};
    for (const int index : calc_tree_order(edges, {0})) {
      model_.joints.push_back(candidates[index]);
      placed.insert(candidates[index].child_link);
    }
    for (int l = 1; l < static_cast<int>(model_.links.size()); ++l) {
      if (placed.count(l) != 0) continue;
      const std::string& name = model_.links[l].name;
      const auto it = parent_joint_.find(l);
      if (it == parent_joint_.end()) {
        fail(lines_.links[name], "body '" + name + "' is disconnected: it is neither fixed (fix) nor the child of a joint");
      }
      fail(lines_.joints[joints_[it->second].name],
           "body '" + name + "' is not connected to a fixed body: joint '" + joints_[it->second].name + "' is part of a cycle");
    }
  }

  std::string path_;
  const DcgParser& parser_;
  std::string directory_;
  ArmModel model_;
  ModelSourceLines lines_;
  std::map<std::string, Entry> body_entries_;
  std::map<std::string, int> link_index_;     // body name -> index into model_.links (world is 0)
  std::set<std::string> mesh_files_;          // the meshes already in model_.input_files
  std::vector<Joint> joints_;                 // file order
  std::map<int, int> parent_joint_;           // child link -> index into joints_
  int ee_line_ = 0;
};

}  // namespace

ArmModel load_dcg_model(const std::string& path) {
  DcgParser parser(path, read_model_file(path));
  const std::vector<Entry> entries = parser.parse();
  return DcgBuilder(path, parser).build(entries);
}

}  // namespace armfarm
