/* report.h - the run report: curve.csv, summary.json, the progress line, final positions (report.c). */
#ifndef FABRIC_REPORT_H
#define FABRIC_REPORT_H

#include "fabric.h"

PetscErrorCode OutputOpen(Fabric fab);
PetscBool      RestartsFrom(const char *dir, const char *restart);
PetscErrorCode OutputCurveRow(Fabric fab, const CurveRow *row);
PetscErrorCode OutputProgress(Fabric fab, const CurveRow *row);
PetscErrorCode OutputSummary(Fabric fab, const char *error, PetscBool together);
PetscErrorCode OutputPositions(Fabric fab, const char *file);

#endif
