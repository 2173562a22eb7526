/* revision.h - which solver made the results (revision.c): the source tree's revision at build
   time (git describe, "-dirty" with uncommitted changes, "unknown" without git), PETSc's version,
   the MPI library. */
#ifndef FABRIC_REVISION_H
#define FABRIC_REVISION_H

#include <stddef.h>

const char *FabricRevision(void);
void        FabricPetscVersion(char *text, size_t len); /* "3.18.5" */
void        FabricMpiLibrary(char *text, size_t len);   /* "Open MPI v4.1.4" */

#endif
