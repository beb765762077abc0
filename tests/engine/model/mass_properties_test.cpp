// Mass properties: closed forms of the primitives against the mesh integrator on tessellated
// copies, the mesh integrator against closed forms (cube, sphere, moved box), and the
// topology checks.
#include "engine/model/mass_properties.hpp"

#include "engine/model/model_loading.hpp"
#include "tests/engine/model/model_test_helpers.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace armfarm {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A closed surface of revolution about z: rings (radius, z) from bottom pole to top pole.
TriangleMesh make_revolved_mesh(const std::vector<std::pair<double, double>>& profile, int segments) {
  TriangleMesh mesh;
  mesh.source_file = "revolved";
  mesh.vertices.emplace_back(0, 0, profile.front().second);
  for (std::size_t i = 1; i + 1 < profile.size(); ++i) {
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * kPi * s / segments;
      mesh.vertices.emplace_back(profile[i].first * std::cos(a), profile[i].first * std::sin(a), profile[i].second);
    }
  }
  mesh.vertices.emplace_back(0, 0, profile.back().second);
  const int rings = static_cast<int>(profile.size()) - 2;
  const int top = static_cast<int>(mesh.vertices.size()) - 1;
  auto ring = [&](int r, int s) { return 1 + r * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) mesh.triangles.emplace_back(0, ring(0, s + 1), ring(0, s));
  for (int r = 0; r + 1 < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      mesh.triangles.emplace_back(ring(r, s), ring(r, s + 1), ring(r + 1, s + 1));
      mesh.triangles.emplace_back(ring(r, s), ring(r + 1, s + 1), ring(r + 1, s));
    }
  }
  for (int s = 0; s < segments; ++s) mesh.triangles.emplace_back(top, ring(rings - 1, s), ring(rings - 1, s + 1));
  mesh.triangle_lines.assign(mesh.triangles.size(), 0);
  return mesh;
}

TriangleMesh make_sphere_mesh(double radius, int rings, int segments) {
  std::vector<std::pair<double, double>> profile;
  for (int i = 0; i <= rings; ++i) {
    const double polar = kPi * (1.0 - static_cast<double>(i) / rings);
    profile.emplace_back(radius * std::sin(polar), radius * std::cos(polar));
  }
  return make_revolved_mesh(profile, segments);
}

TriangleMesh make_capsule_mesh(double radius, double length, int rings_per_cap, int segments) {
  std::vector<std::pair<double, double>> profile;
  for (int i = 0; i <= rings_per_cap; ++i) {  // bottom hemisphere, pole to equator
    const double polar = kPi - 0.5 * kPi * i / rings_per_cap;
    profile.emplace_back(radius * std::sin(polar), radius * std::cos(polar) - length / 2);
  }
  for (int i = 0; i <= rings_per_cap; ++i) {  // top hemisphere, equator to pole
    const double polar = 0.5 * kPi * (1.0 - static_cast<double>(i) / rings_per_cap);
    profile.emplace_back(radius * std::sin(polar), radius * std::cos(polar) + length / 2);
  }
  return make_revolved_mesh(profile, segments);
}

TriangleMesh make_box_mesh(const Eigen::Vector3d& size, const Eigen::Isometry3d& pose) {
  TriangleMesh mesh;
  mesh.source_file = "box";
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner((k & 1 ? 0.5 : -0.5) * size.x(), (k & 2 ? 0.5 : -0.5) * size.y(), (k & 4 ? 0.5 : -0.5) * size.z());
    mesh.vertices.push_back(pose * corner);
  }
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.triangles.emplace_back(q[0], q[1], q[2]);
    mesh.triangles.emplace_back(q[0], q[2], q[3]);
  }
  mesh.triangle_lines.assign(mesh.triangles.size(), 0);
  return mesh;
}

double relative_difference(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) { return (a - b).norm() / b.norm(); }

TEST(MassProperties, ThesisUnitBoxFromObj) {
  const MeshMassProperties cube = calc_mesh_mass_properties(load_obj_mesh(test::data_path("obj/thesis_unit_box.obj")));
  EXPECT_NEAR(cube.volume, 1.0, 1e-12);
  EXPECT_LT(cube.com.norm(), 1e-12);
  EXPECT_LT((cube.unit_density_inertia - Eigen::Matrix3d::Identity() / 6.0).norm(), 1e-12);  // m(a²+a²)/12
}

TEST(MassProperties, CubeWithMixedCornerFormsAndRelativeIndices) {
  const TriangleMesh mesh = load_obj_mesh(test::data_path("obj/unit_cube_mixed.obj"));
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  const MeshMassProperties cube = calc_mesh_mass_properties(mesh);
  EXPECT_NEAR(cube.volume, 1.0, 1e-12);
  EXPECT_LT((cube.com - Eigen::Vector3d::Constant(0.5)).norm(), 1e-12);
  EXPECT_LT((cube.unit_density_inertia - Eigen::Matrix3d::Identity() / 6.0).norm(), 1e-12);
}

TEST(MassProperties, FineSphereApproachesClosedForm) {
  const double radius = 0.3;
  const Inertial exact = calc_sphere_inertial(1.0, radius);
  double previous_error = 1.0;
  for (int rings : {16, 64, 256}) {
    const MeshMassProperties sphere = calc_mesh_mass_properties(make_sphere_mesh(radius, rings, 2 * rings));
    const double error = std::abs(sphere.volume - exact.mass) / exact.mass;
    EXPECT_LT(error, previous_error) << rings;  // converges under refinement
    previous_error = error;
    if (rings == 256) {
      EXPECT_LT(error, 2e-4);
      EXPECT_LT(sphere.com.norm(), 1e-9);
      EXPECT_LT(relative_difference(sphere.unit_density_inertia, exact.inertia), 4e-4);
    }
  }
}

TEST(MassProperties, CappedCylinderClosedFormMatchesTessellation) {
  const double radius = 0.05, length = 0.3, density = 800.0;
  const Inertial exact = calc_capped_cylinder_inertial(density, radius, length);
  EXPECT_NEAR(exact.mass, density * (kPi * radius * radius * length + 4.0 / 3.0 * kPi * std::pow(radius, 3)), 1e-12);
  const MeshMassProperties mesh = calc_mesh_mass_properties(make_capsule_mesh(radius, length, 96, 384));
  const Inertial tessellated = calc_mesh_inertial_for_mass(mesh, exact.mass);
  EXPECT_LT(relative_difference(tessellated.inertia, exact.inertia), 1e-3);
  EXPECT_LT(tessellated.com.norm(), 1e-9);
}

TEST(MassProperties, BoxClosedFormMatchesMesh) {
  const Eigen::Vector3d size(0.1, 0.2, 0.3);
  const Inertial exact = calc_box_inertial(500.0, size);
  EXPECT_NEAR(exact.mass, 3.0, 1e-12);
  EXPECT_NEAR(exact.inertia(0, 0), 3.0 * (0.04 + 0.09) / 12.0, 1e-12);
  const Inertial mesh = calc_mesh_inertial_for_mass(calc_mesh_mass_properties(make_box_mesh(size, Eigen::Isometry3d::Identity())), 3.0);
  EXPECT_LT(relative_difference(mesh.inertia, exact.inertia), 1e-12);
}

TEST(MassProperties, MovedBoxFollowsParallelAxisTheorem) {
  const Eigen::Vector3d size(0.1, 0.2, 0.3);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(5.0, -3.0, 2.0);  // far from the origin: tests conditioning
  const MeshMassProperties moved = calc_mesh_mass_properties(make_box_mesh(size, pose));
  EXPECT_NEAR(moved.volume, size.prod(), 1e-12);
  EXPECT_LT((moved.com - pose.translation()).norm(), 1e-12);
  // About the COM: the box's principal moments rotated into the mesh frame.
  const Inertial box = calc_box_inertial(1.0, size);
  const Eigen::Matrix3d expected = pose.linear() * box.inertia * pose.linear().transpose();
  EXPECT_LT(relative_difference(moved.unit_density_inertia, expected), 1e-10);
  // About the origin: I_com + m (|c|² 1 - c cᵀ).
  const Inertial as_inertial = calc_mesh_inertial_for_mass(moved, moved.volume);
  const Eigen::Vector3d c = pose.translation();
  const Eigen::Matrix3d about_origin = expected + size.prod() * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  EXPECT_LT(relative_difference(calc_inertia_about_origin(as_inertial), about_origin), 1e-10);
  // The transformed-inertial helper agrees with integrating the moved mesh.
  const Inertial transformed = calc_transformed_inertial(box, pose);
  EXPECT_LT(relative_difference(transformed.inertia, expected), 1e-12);
  EXPECT_LT((transformed.com - c).norm(), 1e-12);
}

TEST(MassProperties, OpenMeshIsAnError) {
  const std::string message = test::load_error(test::data_path("bad/open_mesh.dcg"));
  EXPECT_NE(message.find("open_box.obj"), std::string::npos) << message;
  EXPECT_NE(message.find("open mesh"), std::string::npos) << message;
}

TEST(MassProperties, ClockwiseWindingDescribesTheSameSolid) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.3, 0.2, 0.1);
  TriangleMesh mesh = make_box_mesh(Eigen::Vector3d(1, 2, 3), pose);
  const MeshMassProperties outward = calc_mesh_mass_properties(mesh);
  for (Eigen::Vector3i& t : mesh.triangles) std::swap(t[1], t[2]);
  const MeshMassProperties inward = calc_mesh_mass_properties(mesh);
  EXPECT_NEAR(inward.volume, 6.0, 1e-12);
  EXPECT_LT((inward.com - outward.com).norm(), 1e-12);
  EXPECT_LT((inward.unit_density_inertia - outward.unit_density_inertia).norm(), 1e-12);
}

TEST(MassProperties, FlatMeshIsDegenerate) {
  TriangleMesh mesh = make_box_mesh(Eigen::Vector3d(1.0, 1.0, 0.0), Eigen::Isometry3d::Identity());
  try {
    calc_mesh_mass_properties(mesh);
    FAIL() << "no error";
  } catch (const ModelError& error) {
    EXPECT_NE(std::string(error.what()).find("degenerate"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace armfarm
