#include "engine/model/mass_properties.hpp"

#include "engine/model/model_loading.hpp"

#include <cmath>
#include <map>
#include <utility>

namespace armfarm {
namespace {

constexpr double kPi = 3.14159265358979323846;

Inertial diagonal_inertial(double mass, double ixx, double iyy, double izz) {
  Inertial inertial;
  inertial.mass = mass;
  inertial.inertia = Eigen::Vector3d(ixx, iyy, izz).asDiagonal();
  return inertial;
}

std::string edge_text(const TriangleMesh& mesh, int a, int b) {
  return "edge between vertices " + std::to_string(a + 1) + " and " + std::to_string(b + 1) + " (merged numbering) of " +
         mesh.source_file;
}

}  // namespace

Inertial calc_sphere_inertial(double density, double radius) {
  const double mass = density * 4.0 / 3.0 * kPi * radius * radius * radius;
  const double moment = 0.4 * mass * radius * radius;
  return diagonal_inertial(mass, moment, moment, moment);
}

Inertial calc_box_inertial(double density, const Eigen::Vector3d& size) {
  const double mass = density * size.prod();
  const Eigen::Vector3d s2 = size.cwiseProduct(size);
  return diagonal_inertial(mass, mass * (s2.y() + s2.z()) / 12.0, mass * (s2.x() + s2.z()) / 12.0,
                           mass * (s2.x() + s2.y()) / 12.0);
}

Inertial calc_capped_cylinder_inertial(double density, double radius, double length) {
  const double r2 = radius * radius;
  const double cylinder_mass = density * kPi * r2 * length;
  const double caps_mass = density * 4.0 / 3.0 * kPi * r2 * radius;  // both hemispheres
  // Each hemisphere: (83/320) m r² about its own COM (3r/8 from its flat face), shifted to the
  // capsule centre by length/2 + 3r/8; summed over both caps this is caps_mass·(0.4r² + 0.375rl + 0.25l²).
  const double transverse = cylinder_mass * (r2 / 4.0 + length * length / 12.0) +
                            caps_mass * (0.4 * r2 + 0.375 * radius * length + 0.25 * length * length);
  const double axial = cylinder_mass * r2 / 2.0 + caps_mass * 0.4 * r2;
  return diagonal_inertial(cylinder_mass + caps_mass, transverse, transverse, axial);
}

MeshMassProperties calc_mesh_mass_properties(const TriangleMesh& mesh) {
  const std::string& file = mesh.source_file;
  const int n_triangles = static_cast<int>(mesh.triangles.size());
  if (n_triangles < 4) throw ModelError(file + ": degenerate mesh: " + std::to_string(n_triangles) +
                                        " triangles cannot enclose a volume");

  // Topology: a closed, consistently oriented surface uses every directed edge exactly once
  // and its reverse exactly once.
  std::map<std::pair<int, int>, int> directed_edge_triangle;
  for (int t = 0; t < n_triangles; ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    const std::string where = file + ":" + std::to_string(mesh.triangle_lines[t]) + ": ";
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
      throw ModelError(where + "degenerate triangle: it repeats a vertex");
    }
    for (int k = 0; k < 3; ++k) {
      const std::pair<int, int> edge{tri[k], tri[(k + 1) % 3]};
      auto [it, inserted] = directed_edge_triangle.emplace(edge, t);
      if (!inserted) {
        throw ModelError(where + "inconsistent orientation or non-manifold surface: " +
                         edge_text(mesh, edge.first, edge.second) + " is traversed in the same direction by the face on line " +
                         std::to_string(mesh.triangle_lines[it->second]));
      }
    }
  }
  for (const auto& [edge, t] : directed_edge_triangle) {
    if (directed_edge_triangle.count({edge.second, edge.first}) == 0) {
      throw ModelError(file + ":" + std::to_string(mesh.triangle_lines[t]) + ": open mesh (not watertight): " +
                       edge_text(mesh, edge.first, edge.second) + " belongs to only one face");
    }
  }

  // Geometry: integrate over signed tetrahedra (reference point, a, b, c). Using the vertex
  // centroid as reference keeps the sums well conditioned for meshes far from the origin.
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& v : mesh.vertices) reference += v;
  reference /= static_cast<double>(mesh.vertices.size());

  double extent = 0.0;
  for (const Eigen::Vector3d& v : mesh.vertices) extent = std::max(extent, (v - reference).norm());
  if (extent == 0.0) throw ModelError(file + ": degenerate mesh: all vertices coincide");

  double volume = 0.0;
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second_moment = Eigen::Matrix3d::Zero();  // ∫ x xᵀ dV about the reference
  for (int t = 0; t < n_triangles; ++t) {
    const Eigen::Vector3d a = mesh.vertices[mesh.triangles[t][0]] - reference;
    const Eigen::Vector3d b = mesh.vertices[mesh.triangles[t][1]] - reference;
    const Eigen::Vector3d c = mesh.vertices[mesh.triangles[t][2]] - reference;
    const Eigen::Vector3d twice_area = (b - a).cross(c - a);
    if (twice_area.norm() <= 1e-12 * extent * extent) {
      throw ModelError(file + ":" + std::to_string(mesh.triangle_lines[t]) + ": degenerate triangle: zero area");
    }
    const double v = a.dot(b.cross(c)) / 6.0;
    const Eigen::Vector3d sum = a + b + c;
    volume += v;
    first_moment += v * sum / 4.0;
    second_moment += v / 20.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
  }
  if (std::abs(volume) <= 1e-12 * extent * extent * extent) {
    throw ModelError(file + ": degenerate mesh: it encloses zero volume");
  }
  if (volume < 0.0) {
    // Wound clockwise throughout (the thesis's table 5.1 box is): the same solid, integrals negated.
    volume = -volume;
    first_moment = -first_moment;
    second_moment = -second_moment;
  }

  MeshMassProperties properties;
  properties.volume = volume;
  const Eigen::Vector3d com_offset = first_moment / volume;
  properties.com = reference + com_offset;
  const Eigen::Matrix3d about_com = second_moment - volume * com_offset * com_offset.transpose();
  properties.unit_density_inertia = about_com.trace() * Eigen::Matrix3d::Identity() - about_com;
  return properties;
}

Inertial calc_mesh_inertial_for_mass(const MeshMassProperties& properties, double mass) {
  Inertial inertial;
  inertial.mass = mass;
  inertial.com = properties.com;
  inertial.inertia = properties.unit_density_inertia * (mass / properties.volume);
  return inertial;
}

Inertial calc_transformed_inertial(const Inertial& inertial, const Eigen::Isometry3d& pose) {
  Inertial moved = inertial;
  moved.com = pose * inertial.com;
  moved.inertia = pose.linear() * inertial.inertia * pose.linear().transpose();
  return moved;
}

Eigen::Matrix3d calc_inertia_about_origin(const Inertial& inertial) {
  const Eigen::Vector3d& c = inertial.com;
  return inertial.inertia + inertial.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
}

}  // namespace armfarm
