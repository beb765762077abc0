// The bad-model corpus: each file yields one ModelError naming the file, the place and the
// problem, never a crash.
#include "engine/model/model_validation.hpp"

#include "engine/model/model_loading.hpp"
#include "tests/engine/model/model_test_helpers.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace armfarm {
namespace {

struct BadModel {
  const char* file;
  std::vector<std::string> expected;  // substrings: file and place, then the problem
};

const std::vector<BadModel> kCorpus = {
    {"unknown_link.urdf", {"unknown_link.urdf:", ":26:", "joint 'elbow': unknown parent link 'upperr'"}},
    {"cycle.urdf", {"cycle.urdf:", "cycle", "joint 'loop'"}},
    {"two_parents.urdf", {"two_parents.urdf:", "link 'fore' has several parents", "'extra'"}},
    {"disconnected.urdf", {"disconnected.urdf:", "link 'orphan' is disconnected"}},
    {"zero_mass.urdf", {"zero_mass.urdf:4:", "link 'upper'", "zero mass"}},
    {"negative_mass.urdf", {"negative_mass.urdf:", "link 'fore'", "negative mass -2"}},
    {"not_positive_definite.urdf", {"not_positive_definite.urdf:", "link 'upper'", "not positive definite"}},
    {"triangle_inequality.urdf", {"triangle_inequality.urdf:", "link 'fore'", "triangle inequality"}},
    {"nan_origin.urdf", {"nan_origin.urdf:", "<origin> attribute xyz: 'nan' is not a finite number"}},
    {"inf_mass.urdf", {"inf_mass.urdf:", "<mass> attribute value: 'inf' is not a finite number"}},
    {"zero_axis.urdf", {"zero_axis.urdf:", "joint 'elbow': zero axis"}},
    {"lower_above_upper.urdf", {"lower_above_upper.urdf:", "joint 'shoulder'", "lower limit 1.5 > upper limit -1.5"}},
    {"unknown_extension.urdf", {"unknown_extension.urdf:", "unknown element <armfarm:gripper>"}},
    {"transmission_unknown_joint.urdf", {"transmission_unknown_joint.urdf:", "unknown joint 'knee'"}},
    {"floating_joint.urdf", {"floating_joint.urdf:", "joint 'shoulder'", "only revolute, continuous, prismatic and fixed"}},
    {"missing_limit.urdf", {"missing_limit.urdf:", "joint 'elbow': a revolute joint needs <limit"}},
    {"malformed.urdf", {"malformed.urdf:", "XML error"}},
    {"misspelled_axis.urdf", {"misspelled_axis.urdf:23: unknown element <axsi> in <joint> of joint 'elbow' (did you mean <axis>?)"}},
    {"misspelled_mass.urdf", {"misspelled_mass.urdf:29: unknown element <mas> in <inertial> of link 'fore' (did you mean <mass>?)"}},
    {"misspelled_joint.urdf", {"misspelled_joint.urdf:39: unknown element <jiont> in <robot> (did you mean <joint>?)"}},
    {"unknown_tag.dcg", {"unknown_tag.dcg:3:", "body 'arm'", "unknown tag 'q'"}},
    {"unknown_body.dcg", {"unknown_body.dcg:4:", "joint 'ground-hand'", "two defined bodies"}},
    {"missing_mesh.dcg", {"missing_mesh.dcg:3:", "body 'arm'", "no_such_mesh.obj: no such file"}},
    {"open_mesh.dcg", {"open_mesh.dcg:3:", "open_box.obj", "open mesh"}},
    {"flipped_face.dcg", {"flipped_face.dcg:3:", "flipped_face_box.obj:", "inconsistent orientation"}},
    {"degenerate_mesh.dcg", {"degenerate_mesh.dcg:3:", "degenerate.obj:8:", "degenerate triangle"}},
    {"limits_reversed.dcg", {"limits_reversed.dcg:4:", "joint 'ground-arm'", "lower limit"}},
    {"zero_rotation_axis.dcg", {"zero_rotation_axis.dcg:4:", "zero rotation axis"}},
    {"nan_size.dcg", {"nan_size.dcg:3:", "tag s: value 2 is not a finite number: 'nan'"}},
    {"universal_joint.dcg", {"universal_joint.dcg:4:", "j(5) (universal) is not supported"}},
    {"cycle.dcg", {"cycle.dcg:", "cycle"}},
    {"floating_body.dcg", {"floating_body.dcg:5:", "body 'drifter' is disconnected"}},
    {"negative_density.dcg", {"negative_density.dcg:3:", "link 'arm'", "negative mass"}},
    {"missing_semicolon.dcg", {"missing_semicolon.dcg:4:", "entry 'arm' (line 3) is missing its ';'"}},
};

TEST(ModelValidation, BadCorpusGivesOneLineErrorsNamingFilePlaceAndProblem) {
  for (const BadModel& bad : kCorpus) {
    const std::string message = test::load_error(test::data_path(std::string("bad/") + bad.file));
    ASSERT_FALSE(message.empty()) << bad.file << " loaded without error";
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    for (const std::string& part : bad.expected) {
      EXPECT_NE(message.find(part), std::string::npos) << bad.file << ": '" << part << "' not in: " << message;
    }
  }
}

TEST(ModelValidation, EveryCorpusFileIsCovered) {
  EXPECT_GE(kCorpus.size(), 12u);
}

ArmModel make_pendulum() {
  ArmModel model;
  model.source_file = "inline";
  Link base;
  base.name = "base";
  base.fixed_to_world = true;
  Link bob;
  bob.name = "bob";
  bob.inertial.mass = 1.0;
  bob.inertial.inertia = Eigen::Matrix3d::Identity() * 0.01;
  model.links = {base, bob};
  Joint joint;
  joint.name = "swing";
  joint.parent_link = 0;
  joint.child_link = 1;
  joint.effort_limit = joint.velocity_limit = std::numeric_limits<double>::infinity();
  model.joints = {joint};
  model.end_effector.link = 1;
  return model;
}

std::string validation_error(const ArmModel& model, const ModelSourceLines& lines = {}) {
  try {
    validate_arm_model(model, lines);
  } catch (const ModelError& error) {
    return error.what();
  }
  return "";
}

TEST(ModelValidation, InlineModelsReportElementAndLine) {
  ArmModel model = make_pendulum();
  EXPECT_EQ(validation_error(model), "");
  model.joints[0].damping = std::numeric_limits<double>::quiet_NaN();
  ModelSourceLines lines;
  lines.joints["swing"] = 12;
  EXPECT_EQ(validation_error(model, lines), "inline:12: joint 'swing': NaN or Inf in its limits, dynamics, armature or start position");
  model = make_pendulum();
  model.joints[0].axis = Eigen::Vector3d(0, 0, 0.5);
  EXPECT_EQ(validation_error(model), "inline: joint 'swing': axis is not a unit vector (norm 0.5)");
  model = make_pendulum();
  model.links[1].inertial.inertia(0, 1) = 0.001;  // not symmetric
  EXPECT_NE(validation_error(model).find("not symmetric"), std::string::npos);
  model = make_pendulum();
  model.joints[0].has_position_limits = true;
  model.joints[0].lower = -1.0;
  model.joints[0].upper = 1.0;
  model.joints[0].start_position = 2.0;
  EXPECT_NE(validation_error(model).find("start position 2 outside the limits"), std::string::npos);
  model = make_pendulum();
  model.joints[0].armature = -0.1;
  EXPECT_NE(validation_error(model).find("negative armature"), std::string::npos);
}

}  // namespace
}  // namespace armfarm
