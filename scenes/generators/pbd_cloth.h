#pragma once
// A small position-based-dynamics cloth solver (XPBD distance constraints, small steps):
// stretch constraints on the mesh edges, bending constraints between the two vertices
// opposite each interior edge, gravity, wind drag on the triangles, velocity damping, and
// collision response with friction against rigid obstacles. No self-collision response, so
// folds pass through each other: the broad phase sees real self-contact.
//
// Deterministic and thread-count independent: constraints are graph-coloured (greedy, in a
// fixed order) so that one colour's constraints share no vertex and run in parallel; every
// per-vertex pass reads neighbours in a fixed order. Results are bitwise identical for any
// number of OpenMP threads.
#include <cstdint>
#include <functional>
#include <vector>

#include "scenes/generators/colliders.h"
#include "scenes/generators/dvec.h"
#include "cdbench/geometry/mesh.h"

namespace cdb::scene {

struct ClothSettings {
  uint32_t substeps = 12;   // per step; more is stiffer and more accurate
  uint32_t iterations = 1;  // constraint sweeps per substep
  double stretch_compliance = 0.0;
  double bend_compliance = 1e-3;  // larger bends more easily
  double damping = 0.2;           // velocity decay rate, 1/s
  double thickness = 0.01;        // distance kept from obstacles
  double friction = 0.3;          // fraction of tangential slip removed at a contact
  double drag = 0.0;              // wind force per unit area and relative normal speed
  dvec3 gravity{0, -9.81, 0};
};

// Obstacles at time t.
using CollidersAt = std::function<void(double t, Colliders& out)>;
// Wind velocity at time t and point p.
using WindAt = std::function<dvec3(double t, dvec3 p)>;
// Where driven vertices are at time t, one position per driven vertex in order.
using DrivenAt = std::function<void(double t, std::vector<dvec3>& out)>;

class PbdCloth {
 public:
  PbdCloth(std::vector<dvec3> positions, const std::vector<Tri>& faces, const ClothSettings& settings);

  void pin(uint32_t vertex);  // held where it is
  void pin(uint32_t vertex, dvec3 position);  // held at `position`; rest lengths stay
  // Pins `vertices` that move: at every substep each goes where `at` says (a skirt's
  // waistband following a dancing body).
  void drive(std::vector<uint32_t> vertices, DrivenAt at);
  // Advances from time t by dt. The obstacles must keep the same shapes and counts.
  void step(double t, double dt, const CollidersAt& colliders, const WindAt& wind);
  const std::vector<dvec3>& positions() const { return x_; }

 private:
  struct Constraint {
    uint32_t a, b;
    double rest;
    double compliance;
  };
  void colour_constraints();
  void wind_accelerations(double t, const WindAt& wind);
  void project_constraints(double h);
  void collide(const Colliders& colliders, double h);

  ClothSettings s_;
  std::vector<Tri> faces_;
  std::vector<dvec3> x_, prev_, v_, accel_;
  std::vector<double> inv_mass_;
  std::vector<Constraint> constraints_;  // grouped by colour
  std::vector<uint32_t> colour_start_;   // colour c is [colour_start_[c], colour_start_[c+1])
  std::vector<double> lambda_;
  std::vector<uint32_t> vertex_face_start_, vertex_faces_;  // faces around each vertex (CSR)
  std::vector<dvec3> face_force_;
  double mean_vertex_area_ = 1;
  std::vector<int8_t> shell_side_;  // per (open revolved obstacle, vertex)
  bool sides_ready_ = false;
  Colliders colliders_;
  std::vector<uint32_t> driven_;
  DrivenAt driven_at_;
  std::vector<dvec3> driven_to_;
};

}  // namespace cdb::scene
