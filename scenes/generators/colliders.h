#pragma once
// Rigid obstacles as the cloth solver sees them: where a cloth vertex closer than the cloth
// thickness (or inside) goes, and how fast the surface moves there (for friction).
#include <cstdint>
#include <memory>
#include <vector>

#include "scenes/generators/dvec.h"
#include "cdbench/geometry/mesh.h"
#include "scenes/generators/rigid_shapes.h"

namespace cdb::scene {

struct Contact {
  dvec3 normal;            // unit, pointing from the obstacle to the vertex
  dvec3 surface_velocity;  // of the obstacle's surface point at the contact
};

struct SphereCollider {
  dvec3 center;
  double radius = 1;
  dvec3 velocity;
  dvec3 spin;  // angular velocity about the centre
};

struct CapsuleCollider {  // static
  dvec3 a, b;
  double radius = 1;
};

// A surface of revolution about the vertical axis through `origin`. Solid: the profile
// starts and ends on the axis and bounds a volume the cloth stays out of. Open (a funnel):
// a thin shell; each vertex remembers which side it is on and is kept there, except that
// it may pass around the profile's free ends (over a funnel's rim).
struct RevolvedCollider {
  dvec3 origin;
  Profile profile;
  bool solid = false;
  dvec3 velocity;
};

// A deforming triangle mesh (a skinned body) at one instant: its vertices' positions and
// velocities and a uniform grid of its triangles. Built once per substep and shared by every
// cloth vertex's test.
class MeshSurface {
 public:
  // `reach`: the farthest from a triangle (in front or behind) that a vertex is tested.
  MeshSurface(std::shared_ptr<const std::vector<Tri>> faces, std::vector<dvec3> positions,
              std::vector<dvec3> velocities, double reach);
  // The triangle nearest p within `reach`, with the closest point's barycentric weights;
  // false when there is none.
  bool nearest(dvec3 p, uint32_t& face, dvec3& weights, double& distance) const;
  const std::vector<Tri>& faces() const { return *faces_; }
  const std::vector<dvec3>& positions() const { return x_; }
  const std::vector<dvec3>& velocities() const { return v_; }
  const std::vector<dvec3>& normals() const { return n_; }

 private:
  std::shared_ptr<const std::vector<Tri>> faces_;
  std::vector<dvec3> x_, v_, n_;  // n_: unit face normals
  std::vector<dvec3> centre_;      // of each face's bounding sphere, for a cheap first test
  std::vector<double> radius_;
  double reach_, cell_;
  dvec3 lo_;
  int64_t dims_[3] = {1, 1, 1};
  std::vector<uint32_t> cell_start_, cell_faces_;  // CSR: the faces whose reach-grown box meets each cell
};

// A vertex closer than the thickness to the front of the surface, or behind it by less
// than `depth`, goes to `thickness` in front of its nearest triangle. Deeper ones (through
// a thin limb, say) are left where they are: pushing them out would drag the cloth through
// the limb to its other side.
struct MeshCollider {
  std::shared_ptr<const MeshSurface> surface;
  double depth = 0;
};

struct Colliders {
  std::vector<SphereCollider> spheres;
  std::vector<CapsuleCollider> capsules;
  std::vector<RevolvedCollider> revolved;
  std::vector<MeshCollider> meshes;
};

// Each moves p to `thickness` outside the obstacle when it is closer (or inside) and
// returns true with the contact; otherwise leaves p and returns false.
bool resolve(const SphereCollider& s, double thickness, dvec3& p, Contact& c);
bool resolve(const CapsuleCollider& s, double thickness, dvec3& p, Contact& c);
bool resolve(const MeshCollider& m, double thickness, dvec3& p, Contact& c);
// `side` is the vertex's remembered side of an open shell (+1 along the profile's left
// normal, -1 against); unused for solids.
bool resolve(const RevolvedCollider& s, double thickness, dvec3& p, int8_t& side, Contact& c);

// The side of an open shell that p is on, to initialise the remembered sides.
int8_t shell_side(const RevolvedCollider& s, dvec3 p);

}  // namespace cdb::scene
