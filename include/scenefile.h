/* scenefile.h - the scene file and the option files before PETSc reads them; options nothing reads
 * (scenefile.c). */
#ifndef FABRIC_SCENEFILE_H
#define FABRIC_SCENEFILE_H

#include "scene.h"

/* -scene FILE: checked, then inserted, then PETSC_OPTIONS and the command line again, so that they win */
PetscErrorCode SceneInsertFile(MPI_Comm comm, int argc, char **argv);
/* what PETSc's YAML option reader would refuse in text, where (msg); 0: nothing (plain C, before PetscInitialize),
   and then (opts not NULL) the options it would set, with their values, in order (a "$$name: !include F" as
   -options_file_yaml F, then "-$$prefix" P under a key's mapping, whose prefix P PETSc reads F's options under), freed
   by OptionFileFree */
int YamlOptionsProblem(const char *text, char *msg, size_t len, char ***opts, int *nopts);
/* what PETSc's reader of a plain option file (-options_file) would refuse in text, where (msg); 0: nothing, and
   then (opts not NULL) the file's options and values in order, freed by OptionFileFree */
int  OptionFileProblem(const char *text, char *msg, size_t len, char ***opts, int *nopts);
void OptionFileFree(char **opts, int n);
/* an unknown option is an error; with solver_options_later, PETSc's solver options (-snes_*, -ksp_*,
   -pc_*, -mg_*, -mat_*) are left to the quasi-static solver, and SceneWarnUnused names those it has not read
   (when: by when, e.g. "by the solves up to load step 1"), once: a name warned about is marked used */
PetscErrorCode SceneCheckUnused(MPI_Comm comm, PetscBool solver_options_later);
PetscErrorCode SceneWarnUnused(MPI_Comm comm, const char *when);

#endif
