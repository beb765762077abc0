#pragma once
// Generated arm files of any size, for the model size cap and linear loading (issue 30): a URDF
// chain or star of unit-mass links, and the DCG chain of the same shape. Shared by the tests and
// bench_model_loading.
#include <string>

namespace armfarm::test_support {

/// A URDF with a massless root link "base" and `links` unit-mass links l0.. joined by revolute
/// joints j0.. about z, 0.01 m apart: each hanging from the previous one (chain) or all from
/// the base (star, `links` leaves). The file has links + 1 <link> elements.
inline std::string make_big_urdf(int links, bool star) {
  std::string text = "<robot name=\"big\">\n<link name=\"base\"/>\n";
  for (int i = 0; i < links; ++i) {
    text += "<link name=\"l" + std::to_string(i) +
            "\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" "
            "iyz=\"0\"/></inertial></link>\n";
  }
  for (int i = 0; i < links; ++i) {
    const std::string parent = star || i == 0 ? "base" : "l" + std::to_string(i - 1);
    text += "<joint name=\"j" + std::to_string(i) + "\" type=\"revolute\"><parent link=\"" + parent + "\"/><child link=\"l" +
            std::to_string(i) + "\"/><origin xyz=\"0 0 0.01\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" "
            "effort=\"10\" velocity=\"1\"/></joint>\n";
  }
  return text + "</robot>\n";
}

/// A DCG chain: a fixed box "b" and `bodies` − 1 boxes b1.. hinged one to the next, 0.01 m apart.
inline std::string make_big_dcg(int bodies) {
  std::string text = "<DCGraph>\nB b <t(0 0 0)> o(1) s(0.1 0.1 0.01) fix;\n";
  for (int i = 1; i < bodies; ++i) text += "B b" + std::to_string(i) + " <> o(1) s(0.01 0.01 0.01) w(1);\n";
  for (int i = 1; i < bodies; ++i) {
    text += "J " + (i == 1 ? std::string("b") : "b" + std::to_string(i - 1)) + "-b" + std::to_string(i) + " <t(0 0 0.01)>;\n";
  }
  return text + "</DCGraph>\n";
}

}  // namespace armfarm::test_support
