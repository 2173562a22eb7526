/* bodies.h - rigid bodies with penalty contact and Coulomb friction (MODEL.md 5.5).
 *
 * Kernels over n consecutive owned points: arrays in, forces out (no MPI, no options).
 */
#ifndef FABRIC_BODIES_H
#define FABRIC_BODIES_H

#include <petscsys.h>

/* The rigid bodies of a scene, one interface for all (MODEL.md 5.5): where a body is, its
   contact forces and friction on the crossings, its reaction (minus the sum of those forces),
   its penalty energy and tangent (the quasi-static path) and its share of the stable-step
   bound. Friction is path-dependent: it has no energy; its stick spring has the contact
   stiffness, so the bound is the frictionless one. */
typedef enum { BODY_SPHERE, BODY_PLANE, BODY_PEDESTAL, BODY_KINDS } BodyKind;

typedef struct {
  BodyKind  kind;
  PetscReal ref[3]; /* m: the sphere's centre at the start, a point of the plane, the pedestal's top centre */
  PetscReal dir[3]; /* unit: the sphere's path; the plane's normal */
  PetscReal radius; /* m: sphere, pedestal */
  PetscReal height; /* m: pedestal, below its top face */
  PetscReal reach;  /* m: contact distance (half the fabric thickness, plus the sphere's radius) */
  PetscReal k, mu;  /* penalty stiffness per crossing (N/m), Coulomb friction coefficient */
} Body;

extern const char *const BodyNames[BODY_KINDS];

/* where the body is when the load program has moved it by travel (only the sphere moves) */
void BodyPosition(const Body *b, PetscReal travel, PetscReal c[3]);
/* contact (and friction, with anchors) of body b at position c on n consecutive points: adds to f */
void BodyContact(const Body *b, const PetscReal c[3], PetscInt n, const PetscReal *x, const PetscReal *inv_m,
                 PetscReal *anchor, PetscReal *f);
/* penalty energy 0.5 k p^2 of one point at x (p: penetration), its gradient g and Hessian K (3 x 3, row-major) */
PetscReal BodyEnergy(const Body *b, const PetscReal c[3], const PetscReal x[3], PetscReal g[3], PetscReal K[9]);
/* the body's share of the stable-step bound at a point, in contact or not: its penalty spring k
   along its normal there (a frictionless sphere or plane: the penalty's Hessian is at most
   k n n^T), or k in every direction (with friction, whose stick spring is tangential; the
   pedestal, whose normal turns round its edge) */
static inline PetscBool BodyBoundAlongNormal(const Body *b)
{
  return b->mu == 0 && (b->kind == BODY_SPHERE || b->kind == BODY_PLANE) ? PETSC_TRUE : PETSC_FALSE;
}

/* Penalty contact with rigid bodies (MODEL.md 5.5) on n consecutive owned points: a point
   closer than reach (h/2, plus R for a sphere) to the body is pushed out along the surface
   normal with fn = k (reach - distance). Only points with inv_m > 0 feel it. Adds to f (the body's
   reaction is minus the total added: measured as an exact sum in measure.c).
   Coulomb friction (mu > 0, anchor != NULL): a stick spring of stiffness k to a per-point anchor
   (3 per point, relative to the body's reference point: c, p0, top), cut at mu fn (slip);
   anchor is updated (a point out of contact gets its anchor where it is). NULL: frictionless. */
void SphereContact(PetscInt n, const PetscReal *x, const PetscReal *inv_m, const PetscReal c[3], PetscReal reach,
                   PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f);

/* A rigid plane through p0 with unit normal nrm: pushed out along nrm (a point behind it too). */
void PlaneContact(PetscInt n, const PetscReal *x, const PetscReal *inv_m, const PetscReal p0[3], const PetscReal nrm[3],
                  PetscReal reach, PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f);

/* A rigid disc (pedestal): the solid vertical cylinder of the given radius whose flat top face
   is centred on top[3] and faces +z, reaching height below it. The distance is to the nearest
   point of the solid: straight down onto the top face above it, radially onto the rim beside
   it, to the edge circle (a rounded edge of radius reach) around it; a point inside leaves
   through its nearest face (top, rim or bottom). */
void DiscContact(PetscInt n, const PetscReal *x, const PetscReal *inv_m, const PetscReal top[3], PetscReal radius,
                 PetscReal height, PetscReal reach, PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f);

#endif
