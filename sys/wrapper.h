/* Everything signorini binds from PETSc 3.18: vectors, matrices, KSP/PC, SNES (VI), TAO. */
#include <petsc.h>
#include <petscksp.h>
#include <petscsnes.h>
#include <petsctao.h>
#include "shim.h"
