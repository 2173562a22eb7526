/* measure.h - the measurements of a balanced load step for curve.csv (measure.c). */
#ifndef FABRIC_MEASURE_H
#define FABRIC_MEASURE_H

#include "fabric.h"

/* the reactions on the grips, bodies and clamps, the load point's travel, the centre shear
   (bias) and the drape outline (drape: drape_pct, folds, the largest drop in row->travel) */
PetscErrorCode MeasureLoadStep(Fabric fab, CurveRow *row);
/* a curve row as CURVE_COLS numbers and back (checkpoints) */
#define CURVE_COLS 21
void CurveRowPack(const CurveRow *r, PetscReal a[CURVE_COLS]);
void CurveRowUnpack(const PetscReal a[CURVE_COLS], CurveRow *r);
/* drape test, at set-up: the flat specimen's area, measured as the drape's outlines are; the support must leave
   some of it hanging (the nominal disc is wider than the grid's outline: a support between the two gave a drape
   coefficient above 100 %) */
PetscErrorCode DrapeSetUp(Fabric fab);
/* drape test: drape_pct and folds of the current positions, the largest drop into row->travel */
PetscErrorCode DrapeOutline(Fabric fab, CurveRow *row);

#endif
