#pragma once
// Rigid obstacles as the cloth solver sees them: where a cloth vertex closer than the cloth
// thickness (or inside) goes, and how fast the surface moves there (for friction).
#include <cstdint>
#include <vector>

#include "dvec.h"
#include "rigid_shapes.h"

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

struct Colliders {
  std::vector<SphereCollider> spheres;
  std::vector<CapsuleCollider> capsules;
  std::vector<RevolvedCollider> revolved;
};

// Each moves p to `thickness` outside the obstacle when it is closer (or inside) and
// returns true with the contact; otherwise leaves p and returns false.
bool resolve(const SphereCollider& s, double thickness, dvec3& p, Contact& c);
bool resolve(const CapsuleCollider& s, double thickness, dvec3& p, Contact& c);
// `side` is the vertex's remembered side of an open shell (+1 along the profile's left
// normal, -1 against); unused for solids.
bool resolve(const RevolvedCollider& s, double thickness, dvec3& p, int8_t& side, Contact& c);

// The side of an open shell that p is on, to initialise the remembered sides.
int8_t shell_side(const RevolvedCollider& s, dvec3 p);

}  // namespace cdb::scene
