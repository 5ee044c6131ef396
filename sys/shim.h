/* Macros and inline helpers that bindgen cannot translate (MPI handles are pointers in Open MPI,
 * PETSC_COMM_SELF and MPI_COMM_WORLD are macros, PETSC_INFINITY is an expression). */
#ifndef SIGNORINI_SHIM_H
#define SIGNORINI_SHIM_H
#include <petscsys.h>
MPI_Comm signorini_comm_world(void);
MPI_Comm signorini_comm_self(void);
int signorini_comm_rank(MPI_Comm comm, int *rank);
int signorini_comm_size(MPI_Comm comm, int *size);
/* op: 0 = sum, 1 = max, 2 = min. Returns an MPI error code. */
int signorini_allreduce_f64(MPI_Comm comm, const double *in, double *out, int n, int op);
int signorini_allreduce_i64(MPI_Comm comm, const long long *in, long long *out, int n, int op);
/* MPI_Bcast of n bytes from root. Returns an MPI error code. */
int signorini_bcast_bytes(MPI_Comm comm, void *buf, int n, int root);
int signorini_bcast_bytes_sleeping(MPI_Comm comm, void *buf, int n, int root, int sleep_us);
PetscReal signorini_petsc_infinity(void);
PetscBool signorini_mpi_initialized(void);
int signorini_release_free_memory(void);
int signorini_ignore_file_size_signal(void);
#endif
