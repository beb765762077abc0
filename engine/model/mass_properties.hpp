#pragma once
// Mass properties of uniform-density solids: the DCG primitives (sphere, box, capped cylinder)
// in closed form and closed triangle meshes by the signed-tetrahedron decomposition (the same
// volume integrals Mirtich 1996 reduces to surface integrals with the divergence theorem).
// Units: SI (kg, m, kg/m³, kg·m²). Every result is an Inertial: COM in the shape's frame and
// the inertia about the COM in that frame.
#include "engine/model/arm_model.hpp"
#include "engine/model/triangle_mesh.hpp"

namespace armfarm {

/// Solid sphere of radius r (> 0) centred at the origin.
Inertial calc_sphere_inertial(double density, double radius);

/// Solid box with edge lengths (sx, sy, sz) along the frame's axes, centred at the origin.
Inertial calc_box_inertial(double density, const Eigen::Vector3d& size);

/// Capsule along z (ODE's capped cylinder): a cylinder of radius r and length `length`
/// (the straight part) closed by two hemispheres; total extent length + 2r; centred at the origin.
Inertial calc_capped_cylinder_inertial(double density, double radius, double length);

/// Volume (m³), COM and inertia about the COM of the solid bounded by a closed mesh.
struct MeshMassProperties {
  double volume = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d unit_density_inertia = Eigen::Matrix3d::Zero();  ///< about the COM, density 1
};

/// Checks that the mesh is a closed, consistently oriented surface without degenerate triangles
/// and integrates it. A mesh wound clockwise throughout (normals inward) describes the same
/// solid and gives the same result. Throws ModelError naming the mesh file and the offending
/// triangle (its `f` line) or edge: "open mesh", "inconsistent orientation", "degenerate ...".
MeshMassProperties calc_mesh_mass_properties(const TriangleMesh& mesh);

/// The Inertial of a uniform solid of the given mass with the mesh's shape.
Inertial calc_mesh_inertial_for_mass(const MeshMassProperties& properties, double mass);

/// Mass properties of a body moved by `pose` (the body's frame expressed in a new frame):
/// COM mapped by the pose, inertia rotated (R I Rᵀ); mass unchanged.
Inertial calc_transformed_inertial(const Inertial& inertial, const Eigen::Isometry3d& pose);

/// The inertia of `inertial` about the origin of its frame (parallel-axis theorem).
Eigen::Matrix3d calc_inertia_about_origin(const Inertial& inertial);

}  // namespace armfarm
