/* bodies.h - rigid bodies with penalty contact and Coulomb friction (MODEL.md 5.5).
 *
 * Kernels over n consecutive owned points: arrays in, forces out (no MPI, no options).
 */
#ifndef FABRIC_BODIES_H
#define FABRIC_BODIES_H

#include <petscsys.h>

/* Penalty contact with rigid bodies (MODEL.md 5.5) on n consecutive owned points: a point
   closer than reach (h/2, plus R for a sphere) to the body is pushed out along the surface
   normal with fn = k (reach - distance). Only points with inv_m > 0 feel it. Adds to f, and the
   added forces to sum[3] (the body's reaction is minus their total).
   Coulomb friction (mu > 0, anchor != NULL): a stick spring of stiffness k to a per-point anchor
   (3 per point, relative to the body's reference point: c, p0, top), cut at mu fn (slip);
   anchor is updated (a point out of contact gets its anchor where it is). NULL: frictionless. */
void SphereContact(PetscInt n, const PetscReal *x, const PetscReal *inv_m, const PetscReal c[3], PetscReal reach,
                   PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f, PetscReal sum[3]);

/* A rigid plane through p0 with unit normal nrm: pushed out along nrm (a point behind it too). */
void PlaneContact(PetscInt n, const PetscReal *x, const PetscReal *inv_m, const PetscReal p0[3], const PetscReal nrm[3],
                  PetscReal reach, PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f, PetscReal sum[3]);

/* A rigid disc (pedestal): the solid vertical cylinder of the given radius whose flat top face
   is centred on top[3] and faces +z, reaching height below it. The distance is to the nearest
   point of the solid: straight down onto the top face above it, radially onto the rim beside
   it, to the edge circle (a rounded edge of radius reach) around it; a point inside leaves
   through its nearest face (top, rim or bottom). */
void DiscContact(PetscInt n, const PetscReal *x, const PetscReal *inv_m, const PetscReal top[3], PetscReal radius,
                 PetscReal height, PetscReal reach, PetscReal k, PetscReal mu, PetscReal *anchor, PetscReal *f,
                 PetscReal sum[3]);

#endif
