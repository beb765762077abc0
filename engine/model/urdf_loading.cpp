// URDF → ArmModel. urdfdom reads the standard elements; a tinyxml2 pass over the same text
// first checks names, references, numbers and the element names inside <link> and <joint> (so
// messages carry line numbers, which urdfdom's console messages do not, and a misspelled
// <axsi> is an error instead of a silently default axis) and reads what urdfdom skips:
// transmissions and armfarm extensions. Extension elements (namespaced ones such as drake:*,
// <gazebo>, <ros2_control>, <frame>, …) are skipped.
#include "base/did_you_mean.hpp"
#include "engine/io/message_text.hpp"
#include "engine/model/model_file.hpp"
#include "engine/model/model_loaders.hpp"
#include "engine/model/model_loading.hpp"
#include "engine/model/model_validation.hpp"
#include "engine/model/start_posture.hpp"

#include <console_bridge/console.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <algorithm>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

namespace armfarm {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The URDF elements urdfdom reads, by parent (ROS wiki "urdf/XML"; urdfdom's parser). Inside
// <link> and <joint> (and their core children) an element that is not one of these is
//   - skipped silently when namespaced (prefix:name, e.g. drake:*);
//   - an error when it is one or two edits away from an allowed name (<axsi>: a misspelling);
//   - otherwise skipped with a warning (ArmModel::warnings; --strict refuses it): ROS's own
//     tutorial suggests custom elements such as <collision_checking> inside <link>, and vendor
//     files carry <self_collision_checking> (PR2, iiwa) and <material> inside <collision>.
// At the top level, names that are not core are extensions (gazebo, ros2_control, frame, ...) and
// skipped silently, unless they are one or two edits away from link, joint or material.
const std::map<std::string, std::set<std::string>>& core_children() {
  static const std::map<std::string, std::set<std::string>> children = {
      {"robot", {"link", "joint", "material", "transmission", "gazebo"}},
      {"link", {"inertial", "visual", "collision"}},
      {"joint", {"origin", "parent", "child", "axis", "calibration", "dynamics", "limit", "safety_controller", "mimic"}},
      {"inertial", {"origin", "mass", "inertia"}},
      {"visual", {"origin", "geometry", "material"}},
      {"collision", {"origin", "geometry", "material"}},  // material: urdfdom ignores it there; vendor files carry it
      {"geometry", {"box", "cylinder", "sphere", "mesh", "capsule"}},
      {"material", {"color", "texture"}},
  };
  return children;
}

// What the tinyxml2 pass learns besides the checks.
struct UrdfExtras {
  ModelSourceLines lines;
  std::vector<std::string> link_order;              // document order
  std::map<std::string, double> armature;           // joint name -> kg·m²
  std::map<std::string, double> start_position;     // joint name -> rad or m
  std::string end_effector_link;                    // empty: default
  Eigen::Vector3d end_effector_offset = Eigen::Vector3d::Zero();
  int end_effector_line = 0;
  std::vector<std::string> warnings;  // "file:line: <x> in <link> of link 'y' is not a URDF element"
};

class UrdfScanner {
 public:
  explicit UrdfScanner(std::string path) : path_(std::move(path)) {}

  /// The checks and the extras of the document, in this order: the root, the size cap, element
  /// names, links, joints, the tree, transmissions, armfarm extensions. Throws ModelError
  /// "FILE:LINE: what" at the first problem.
  UrdfExtras scan(const tinyxml2::XMLDocument& document) {
    const tinyxml2::XMLElement* robot = document.FirstChildElement("robot");
    if (robot == nullptr) fail(1, "the root element must be <robot>");
    check_size(robot);
    check_element_names(robot);
    for (const auto* e = robot->FirstChildElement("link"); e != nullptr; e = e->NextSiblingElement("link")) scan_link(e);
    for (const auto* e = robot->FirstChildElement("joint"); e != nullptr; e = e->NextSiblingElement("joint")) scan_joint(e);
    check_tree(robot);
    for (const auto* e = robot->FirstChildElement("transmission"); e != nullptr;
         e = e->NextSiblingElement("transmission")) {
      scan_transmission(e);
    }
    for (const auto* e = robot->FirstChildElement(); e != nullptr; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      if (tag.rfind("armfarm:", 0) == 0) scan_extension(e, tag);
    }
    return extras_;
  }

 private:
  /// A <link>: a unique name (its line and document order recorded), finite numbers.
  void scan_link(const tinyxml2::XMLElement* e) {
    const std::string name = required_attribute(e, "name");
    if (!extras_.lines.links.emplace(name, e->GetLineNum()).second) fail(e, "duplicate link name '" + name + "'");
    extras_.link_order.push_back(name);
    check_numbers(e);
  }

  /// A <joint>: a unique name, known parent and child links, a non-zero axis (unless fixed),
  /// <limit> on revolute and prismatic joints, no <mimic>, finite numbers, and a child link
  /// that is not its own parent and has no other parent joint (recorded for check_tree).
  void scan_joint(const tinyxml2::XMLElement* e) {
    const std::string name = required_attribute(e, "name");
    if (!extras_.lines.joints.emplace(name, e->GetLineNum()).second) fail(e, "duplicate joint name '" + name + "'");
    for (const char* side : {"parent", "child"}) {
      const auto* ref = e->FirstChildElement(side);
      if (ref == nullptr) fail(e, "joint '" + name + "' has no <" + side + ">");
      const std::string link = required_attribute(ref, "link");
      if (extras_.lines.links.count(link) == 0) {
        fail(ref, "joint '" + name + "': unknown " + side + " link '" + link + "'");
      }
    }
    const char* type = e->Attribute("type");
    // A fixed joint has no axis to speak of: vendor files (Kinova's, Jaco's) write <axis xyz="0 0 0"/> there.
    const bool fixed = type != nullptr && std::string(type) == "fixed";
    if (const auto* axis = e->FirstChildElement("axis"); axis != nullptr && !fixed) {
      const Eigen::Vector3d xyz = vector_attribute(axis, "xyz");
      if (xyz.norm() < 1e-12) fail(axis, "joint '" + name + "': zero axis");
    }
    if (type != nullptr && (std::string(type) == "revolute" || std::string(type) == "prismatic") &&
        e->FirstChildElement("limit") == nullptr) {
      fail(e, "joint '" + name + "': a " + type + " joint needs <limit lower upper effort velocity>");
    }
    if (e->FirstChildElement("mimic") != nullptr) fail(e, "joint '" + name + "': mimic joints are not supported");
    check_numbers(e);
    const std::string parent = e->FirstChildElement("parent")->Attribute("link");
    const std::string child = e->FirstChildElement("child")->Attribute("link");
    if (parent == child) fail(e, "joint '" + name + "' connects link '" + child + "' to itself");
    if (const auto it = parent_of_.find(child); it != parent_of_.end()) {
      fail(e, "link '" + child + "' has several parents (joint '" + name + "' and joint '" + it->second.joint + "')");
    }
    parent_of_.emplace(child, ParentRef{parent, name, e->GetLineNum()});
  }

  /// An armfarm:* element at the top level: <armfarm:end_effector link=".." offset="x y z"/>
  /// (once) or <armfarm:start_position joint=".." value=".."/> (once per joint); any other is an error.
  void scan_extension(const tinyxml2::XMLElement* e, const std::string& tag) {
    if (tag == "armfarm:end_effector") {
      if (!extras_.end_effector_link.empty()) fail(e, "second <armfarm:end_effector>");
      extras_.end_effector_link = required_attribute(e, "link");
      if (extras_.lines.links.count(extras_.end_effector_link) == 0) {
        fail(e, "<armfarm:end_effector>: unknown link '" + extras_.end_effector_link + "'");
      }
      if (e->Attribute("offset") != nullptr) extras_.end_effector_offset = vector_attribute(e, "offset");
      extras_.end_effector_line = e->GetLineNum();
    } else if (tag == "armfarm:start_position") {
      const std::string joint = required_attribute(e, "joint");
      if (extras_.lines.joints.count(joint) == 0) fail(e, "<armfarm:start_position>: unknown joint '" + joint + "'");
      if (!extras_.start_position.emplace(joint, number_attribute(e, "value")).second) {
        fail(e, "second start position for joint '" + joint + "'");
      }
    } else {
      fail(e, "unknown element <" + tag + "> (armfarm extensions: <armfarm:end_effector>, <armfarm:start_position>)");
    }
  }

  [[noreturn]] void fail(int line, const std::string& what) const {
    throw ModelError(path_ + ":" + std::to_string(line) + ": " + what);
  }
  [[noreturn]] void fail(const tinyxml2::XMLElement* e, const std::string& what) const { fail(e->GetLineNum(), what); }

  // At most kMaxModelLinks links and as many joints, counted before anything is built from them.
  void check_size(const tinyxml2::XMLElement* robot) const {
    for (const char* kind : {"link", "joint"}) {
      int count = 0;
      for (const auto* e = robot->FirstChildElement(kind); e != nullptr; e = e->NextSiblingElement(kind)) ++count;
      if (count > kMaxModelLinks) {
        throw ModelError(path_ + ": " + std::to_string(count) + " " + kind + "s, over the cap of " +
                         std::to_string(kMaxModelLinks) + " per arm model");
      }
    }
  }

  // Core elements may hold only core elements (or extensions); see core_children().
  void check_element_names(const tinyxml2::XMLElement* robot) {
    const std::set<std::string>& top = core_children().at("robot");
    for (const auto* e = robot->FirstChildElement(); e != nullptr; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      if (top.count(tag) != 0 || tag.find(':') != std::string::npos) continue;
      const std::string close = find_closest_name(tag, {"link", "joint", "material"}, NameMatch{2}).value_or("");
      if (!close.empty()) fail(e, "unknown element <" + tag + "> in <robot> (did you mean <" + close + ">?)");
    }
    std::function<void(const tinyxml2::XMLElement*, const std::string&)> visit = [&](const tinyxml2::XMLElement* e,
                                                                                     const std::string& owner) {
      const auto allowed = core_children().find(e->Name());
      if (allowed == core_children().end()) return;  // a leaf element (origin, mass, box, ...)
      for (const auto* child = e->FirstChildElement(); child != nullptr; child = child->NextSiblingElement()) {
        const std::string tag = child->Name();
        if (tag.find(':') != std::string::npos) continue;  // namespaced extension (drake:*, ...)
        if (allowed->second.count(tag) == 0) {
          const std::string close = find_closest_name(tag, allowed->second, NameMatch{2}).value_or("");
          const std::string where = "<" + tag + "> in <" + e->Name() + "> of " + owner;
          if (!close.empty()) fail(child, "unknown element " + where + " (did you mean <" + close + ">?)");
          extras_.warnings.push_back(path_ + ":" + std::to_string(child->GetLineNum()) + ": " + where + " is not a URDF element");
          continue;
        }
        visit(child, owner);
      }
    };
    for (const char* kind : {"link", "joint", "material"}) {
      for (const auto* e = robot->FirstChildElement(kind); e != nullptr; e = e->NextSiblingElement(kind)) {
        const char* name = e->Attribute("name");
        visit(e, std::string(kind) + " '" + (name == nullptr ? "" : name) + "'");
      }
    }
  }

  std::string required_attribute(const tinyxml2::XMLElement* e, const char* name) const {
    const char* value = e->Attribute(name);
    if (value == nullptr || *value == '\0') fail(e, "<" + std::string(e->Name()) + "> needs a '" + name + "' attribute");
    return value;
  }

  std::vector<double> numbers(const tinyxml2::XMLElement* e, const char* attribute, const std::string& text) const {
    std::vector<double> values;
    std::istringstream tokens(text);
    std::string token;
    while (tokens >> token) {
      char* end = nullptr;
      errno = 0;
      const double value = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(value)) {
        fail(e, "<" + std::string(e->Name()) + "> attribute " + attribute + ": '" + token + "' is not a finite number");
      }
      values.push_back(value);
    }
    return values;
  }

  double number_attribute(const tinyxml2::XMLElement* e, const char* attribute) const {
    const std::vector<double> values = numbers(e, attribute, required_attribute(e, attribute));
    if (values.size() != 1) fail(e, "<" + std::string(e->Name()) + "> attribute " + attribute + " needs one number");
    return values[0];
  }

  Eigen::Vector3d vector_attribute(const tinyxml2::XMLElement* e, const char* attribute) const {
    const std::vector<double> values = numbers(e, attribute, required_attribute(e, attribute));
    if (values.size() != 3) fail(e, "<" + std::string(e->Name()) + "> attribute " + attribute + " needs three numbers");
    return Eigen::Vector3d(values[0], values[1], values[2]);
  }

  double element_number(const tinyxml2::XMLElement* e) const {
    const char* text = e->GetText();
    const std::vector<double> values = numbers(e, "text", text == nullptr ? "" : text);
    if (values.size() != 1) fail(e, "<" + std::string(e->Name()) + "> needs one number");
    return values[0];
  }

  // Every numeric attribute of the elements urdfdom reads must be a finite number.
  void check_numbers(const tinyxml2::XMLElement* element) const {
    static const std::map<std::string, std::set<std::string>> numeric = {
        {"origin", {"xyz", "rpy"}},
        {"axis", {"xyz"}},
        {"limit", {"lower", "upper", "effort", "velocity"}},
        {"dynamics", {"damping", "friction"}},
        {"mass", {"value"}},
        {"inertia", {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"}},
    };
    std::function<void(const tinyxml2::XMLElement*)> visit = [&](const tinyxml2::XMLElement* e) {
      const auto it = numeric.find(e->Name());
      if (it != numeric.end()) {
        for (const auto* a = e->FirstAttribute(); a != nullptr; a = a->Next()) {
          if (it->second.count(a->Name()) != 0) numbers(e, a->Name(), a->Value());
        }
      }
      for (const auto* child = e->FirstChildElement(); child != nullptr; child = child->NextSiblingElement()) visit(child);
    };
    visit(element);
  }

  // ROS-style <transmission>: one <joint name=..>, one <actuator> with <mechanicalReduction>
  // and armfarm's <rotorInertia> (kg·m² about the motor shaft), or Drake's
  // <drake:rotor_inertia value=..> and <drake:gear_ratio value=..> (the ratio defaults to the
  // mechanical reduction). armature = rotor inertia · ratio².
  void scan_transmission(const tinyxml2::XMLElement* e) {
    const auto* joint = e->FirstChildElement("joint");
    if (joint == nullptr) fail(e, "<transmission> without a <joint>");
    if (joint->NextSiblingElement("joint") != nullptr) {
      fail(e, "<transmission> with several joints (only simple one-joint transmissions are supported)");
    }
    const std::string name = required_attribute(joint, "name");
    if (extras_.lines.joints.count(name) == 0) fail(joint, "<transmission>: unknown joint '" + name + "'");
    const auto* actuator = e->FirstChildElement("actuator");
    if (actuator == nullptr) fail(e, "<transmission> for joint '" + name + "' has no <actuator>");
    double reduction = 1.0;
    if (const auto* r = actuator->FirstChildElement("mechanicalReduction")) reduction = element_number(r);
    if (const auto* r = e->FirstChildElement("mechanicalReduction")) reduction = element_number(r);  // old ROS style
    if (reduction == 0.0) fail(actuator, "<mechanicalReduction> of joint '" + name + "' is zero");
    double rotor_inertia = 0.0;
    const auto* ours = actuator->FirstChildElement("rotorInertia");
    const auto* drake = actuator->FirstChildElement("drake:rotor_inertia");
    if (ours != nullptr && drake != nullptr) fail(drake, "joint '" + name + "': both <rotorInertia> and <drake:rotor_inertia>");
    if (ours != nullptr) rotor_inertia = element_number(ours);
    if (drake != nullptr) {
      rotor_inertia = number_attribute(drake, "value");
      if (const auto* ratio = actuator->FirstChildElement("drake:gear_ratio")) reduction = number_attribute(ratio, "value");
      if (reduction == 0.0) fail(actuator, "the gear ratio of joint '" + name + "' is zero");
    }
    if (rotor_inertia < 0.0) fail(ours != nullptr ? ours : drake, "the rotor inertia of joint '" + name + "' is negative");
    if (!extras_.armature.emplace(name, rotor_inertia * reduction * reduction).second) {
      fail(e, "second <transmission> for joint '" + name + "'");
    }
  }

  // The links must form one tree: exactly one link without a parent, and no cycles.
  void check_tree(const tinyxml2::XMLElement* robot) const {
    std::vector<std::string> roots;
    for (const std::string& link : extras_.link_order) {
      if (parent_of_.count(link) == 0) roots.push_back(link);
    }
    // Cycles, in time linear in the links: walk up from each link until a link already known to
    // reach a root (or to be a root); meeting a link of the current walk again closes a loop.
    enum class State { unknown, on_walk, reaches_root };
    std::map<std::string, State> state;
    for (const std::string& link : extras_.link_order) state[link] = State::unknown;
    std::vector<const std::string*> walk;
    for (const std::string& start : extras_.link_order) {
      walk.clear();
      const std::string* link = &start;
      while (state[*link] == State::unknown) {
        state[*link] = State::on_walk;
        walk.push_back(link);
        const auto it = parent_of_.find(*link);
        if (it == parent_of_.end()) break;  // a root
        if (state[it->second.link] == State::on_walk) {
          fail(it->second.line, "cycle: joint '" + it->second.joint + "' closes a loop through link '" + it->second.link + "'");
        }
        link = &it->second.link;
      }
      for (const std::string* done : walk) state[*done] = State::reaches_root;
    }
    if (roots.empty()) fail(robot, "no links");
    if (roots.size() > 1) {
      fail(extras_.lines.links.at(roots[1]), "link '" + roots[1] + "' is disconnected: no joint connects it to the tree of '" +
                                                 roots[0] + "'");
    }
  }

  struct ParentRef {
    std::string link;
    std::string joint;
    int line = 0;
  };
  std::string path_;
  UrdfExtras extras_;
  std::map<std::string, ParentRef> parent_of_;  // child link -> its parent joint
};

// urdfdom reports through console_bridge, whose output handler is one per process and prints
// to the terminal by default. A job's model is loaded on worker threads, several at once, so the
// handler installed here keeps nothing itself: it hands each message to the sink of the thread
// that is parsing (parse_urdf_quietly), and drops messages of threads that have none.
thread_local std::vector<std::string>* urdfdom_sink = nullptr;

class UrdfdomMessageRouter : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (urdfdom_sink == nullptr || level < console_bridge::CONSOLE_BRIDGE_LOG_ERROR) return;
    std::string line = text;  // one line, printable: urdfdom's texts quote the file's names
    for (char& c : line) {
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
    }
    urdfdom_sink->push_back(line);
  }
};

// urdf::parseURDF with urdfdom's error messages collected in `errors` instead of printed.
urdf::ModelInterfaceSharedPtr parse_urdf_quietly(const std::string& xml, std::vector<std::string>& errors) {
  static UrdfdomMessageRouter router;  // stateless; installed once, for the whole process
  static const bool installed = [] {
    console_bridge::useOutputHandler(&router);
    return true;
  }();
  (void)installed;
  urdfdom_sink = &errors;
  struct Reset {
    ~Reset() { urdfdom_sink = nullptr; }
  } reset;
  return urdf::parseURDF(xml);
}

Eigen::Isometry3d to_isometry(const urdf::Pose& pose) {
  double x = 0.0, y = 0.0, z = 0.0, w = 1.0;
  pose.rotation.getQuaternion(x, y, z, w);
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
  transform.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  return transform;
}

/// The file's text as an XML document (the checks' and the extensions' pass reads it). Throws
/// ModelError "FILE:LINE: XML error: NAME" for text that is not well-formed XML.
void parse_xml_document(const std::string& path, const std::string& xml, tinyxml2::XMLDocument& document) {
  if (document.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS) {
    throw ModelError(path + ":" + std::to_string(document.ErrorLineNum()) + ": XML error: " + document.ErrorName());
  }
}

/// urdfdom's reading of the file. Throws ModelError with urdfdom's reasons (the first 3,
/// shortened) when it rejects a file the tinyxml2 pass accepted.
urdf::ModelInterfaceSharedPtr parse_urdf(const std::string& path, const std::string& xml) {
  std::vector<std::string> urdfdom_errors;
  urdf::ModelInterfaceSharedPtr urdf = parse_urdf_quietly(xml, urdfdom_errors);
  if (!urdf) {
    throw ModelError(path + ": not a valid URDF: urdfdom rejected it" +
                     (urdfdom_errors.empty() ? std::string(" (it gave no reason)") : ": " + join_shortened(urdfdom_errors, "; ", 3)));
  }
  return urdf;
}

/// A link's <inertial> in the link frame: mass (kg), centre of mass (m) and the inertia about
/// it (kg·m²), rotated from the inertial frame (origin rpy) into the link frame: R·I·Rᵀ.
Inertial to_inertial(const urdf::Inertial& in) {
  Eigen::Matrix3d inertia;
  inertia << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  const Eigen::Isometry3d frame = to_isometry(in.origin);  // inertial frame in the link frame
  Inertial inertial;
  inertial.mass = in.mass;
  inertial.com = frame.translation();
  inertial.inertia = frame.linear() * inertia * frame.linear().transpose();
  return inertial;
}

/// The links, in document order, appended to model.links; returns each name's index there (a
/// map: find_link per joint would make loading quadratic). A link without <inertial> is massless.
std::unordered_map<std::string, int> add_links(ArmModel& model, const urdf::ModelInterface& urdf,
                                               const std::vector<std::string>& link_order) {
  std::unordered_map<std::string, int> link_index;
  for (const std::string& name : link_order) {
    link_index.emplace(name, static_cast<int>(model.links.size()));
    const urdf::LinkConstSharedPtr source = urdf.getLink(name);
    Link link;
    link.name = name;
    if (source->inertial) link.inertial = to_inertial(*source->inertial);
    model.links.push_back(link);
  }
  return link_index;
}

/// ArmModel's type of a URDF joint. Throws ModelError naming the file, the joint's line and its
/// name for the types armfarm does not simulate (floating, planar).
JointType to_joint_type(const std::string& path, const urdf::Joint& source, const UrdfExtras& extras) {
  switch (source.type) {
    case urdf::Joint::REVOLUTE: return JointType::revolute;
    case urdf::Joint::CONTINUOUS: return JointType::continuous;
    case urdf::Joint::PRISMATIC: return JointType::prismatic;
    case urdf::Joint::FIXED: return JointType::fixed;
    default:
      throw ModelError(path + ":" + std::to_string(extras.lines.joints.at(source.name)) + ": joint '" + source.name +
                       "': only revolute, continuous, prismatic and fixed joints are supported");
  }
}

/// One joint from urdfdom's reading of it: its links (`edge`), origin in the parent link frame,
/// unit axis, type, limits (URDF writes 0 or nothing for "no limit": infinite effort and velocity;
/// position limits on revolute and prismatic joints only; negative values are kept for
/// validate_arm_model to reject), damping and friction; from the tinyxml2 pass its armature
/// (kg·m²) and start position (rad or m; else calc_default_start_position). Throws ModelError
/// naming the file, the joint's line and its name for an unsupported joint type.
Joint make_joint(const std::string& path, const urdf::Joint& source, const TreeEdge& edge, const UrdfExtras& extras) {
  const std::string& name = source.name;
  Joint joint;
  joint.name = name;
  joint.parent_link = edge.parent_link;
  joint.child_link = edge.child_link;
  joint.origin = to_isometry(source.parent_to_joint_origin_transform);
  joint.axis = Eigen::Vector3d(source.axis.x, source.axis.y, source.axis.z);
  if (joint.axis.norm() > 0.0) joint.axis.normalize();
  joint.type = to_joint_type(path, source, extras);
  joint.effort_limit = kInfinity;
  joint.velocity_limit = kInfinity;
  if (source.limits) {
    // URDF writes 0 (or nothing) for "no limit given"; negative values are kept and rejected.
    if (source.limits->effort != 0.0) joint.effort_limit = source.limits->effort;
    if (source.limits->velocity != 0.0) joint.velocity_limit = source.limits->velocity;
    if (joint.type == JointType::revolute || joint.type == JointType::prismatic) {
      joint.has_position_limits = true;
      joint.lower = source.limits->lower;
      joint.upper = source.limits->upper;
    }
  }
  if (source.dynamics) {
    joint.damping = source.dynamics->damping;
    joint.friction = source.dynamics->friction;
  }
  if (const auto it = extras.armature.find(name); it != extras.armature.end()) joint.armature = it->second;
  if (const auto it = extras.start_position.find(name); it != extras.start_position.end()) {
    joint.start_position = it->second;
    joint.start_position_from_file = true;
  } else {
    joint.start_position = calc_default_start_position(joint);
  }
  return joint;
}

/// The joints appended to model.joints in tree order (calc_tree_order): depth first from the
/// root link, children in document order. Throws ModelError as make_joint does.
void add_joints(ArmModel& model, const std::string& path, const tinyxml2::XMLDocument& document, const urdf::ModelInterface& urdf,
                const UrdfExtras& extras, const std::unordered_map<std::string, int>& link_index) {
  std::vector<std::string> joint_names;
  std::vector<TreeEdge> edges;
  for (const tinyxml2::XMLElement* e = document.FirstChildElement("robot")->FirstChildElement("joint"); e != nullptr;
       e = e->NextSiblingElement("joint")) {
    const urdf::JointConstSharedPtr source = urdf.getJoint(e->Attribute("name"));
    joint_names.push_back(source->name);
    edges.push_back({link_index.at(source->parent_link_name), link_index.at(source->child_link_name)});
  }
  for (const int index : calc_tree_order(edges, {model.root_link})) {
    model.joints.push_back(make_joint(path, *urdf.getJoint(joint_names[index]), edges[index], extras));
  }
}

}  // namespace

ArmModel load_urdf_model(const std::string& path) {
  const std::string xml = read_model_file(path);
  tinyxml2::XMLDocument document;
  parse_xml_document(path, xml, document);
  const UrdfExtras extras = UrdfScanner(path).scan(document);
  const urdf::ModelInterfaceSharedPtr urdf = parse_urdf(path, xml);

  ArmModel model;
  model.name = urdf->getName();
  model.source_file = path;
  model.input_files = {path};  // URDF geometry (meshes) is not read
  model.warnings = extras.warnings;
  const std::unordered_map<std::string, int> link_index = add_links(model, *urdf, extras.link_order);
  model.root_link = link_index.at(urdf->getRoot()->name);
  // Only the root is fixed to the world: a mounted base welded to it by a fixed joint still
  // counts in total_mass(), as in a data sheet's robot mass.
  model.links[model.root_link].fixed_to_world = true;
  add_joints(model, path, document, *urdf, extras, link_index);

  // The file's end effector, if it names one; otherwise choose_end_effector decides.
  if (!extras.end_effector_link.empty()) {
    model.end_effector.link = link_index.at(extras.end_effector_link);
    model.end_effector.offset = extras.end_effector_offset;
  }

  validate_arm_model(model, extras.lines);
  return model;
}

}  // namespace armfarm
