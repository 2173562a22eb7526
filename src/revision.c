/* revision.c - which solver made the results: the source tree's revision at build time
 * (revision_id.h, written into the build directory by CMakeLists.txt at every build), PETSc's
 * version and the MPI library's.
 */
#include "revision.h"
#include "revision_id.h"

#include <petscsys.h>

const char *FabricRevision(void)
{
  return FABRIC_REVISION;
}

/* "3.18.5" */
void FabricPetscVersion(char *text, size_t len)
{
  snprintf(text, len, "%d.%d.%d", PETSC_VERSION_MAJOR, PETSC_VERSION_MINOR, PETSC_VERSION_SUBMINOR);
}

/* MPI_Get_library_version's first part: "Open MPI v4.1.4" */
void FabricMpiLibrary(char *text, size_t len)
{
  char lib[MPI_MAX_LIBRARY_VERSION_STRING];
  int  n = 0;

  if (MPI_Get_library_version(lib, &n) != MPI_SUCCESS) n = 0;
  lib[n < MPI_MAX_LIBRARY_VERSION_STRING ? n : MPI_MAX_LIBRARY_VERSION_STRING - 1] = 0;
  lib[strcspn(lib, ",\n")] = 0;
  snprintf(text, len, "%s", lib);
}
