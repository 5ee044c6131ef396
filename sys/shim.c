#include "shim.h"

MPI_Comm signorini_comm_world(void) { return PETSC_COMM_WORLD; }
MPI_Comm signorini_comm_self(void) { return PETSC_COMM_SELF; }
int signorini_comm_rank(MPI_Comm comm, int *rank) { return MPI_Comm_rank(comm, rank); }
int signorini_comm_size(MPI_Comm comm, int *size) { return MPI_Comm_size(comm, size); }

static MPI_Op op_of(int op) { return op == 1 ? MPI_MAX : (op == 2 ? MPI_MIN : MPI_SUM); }

int signorini_allreduce_f64(MPI_Comm comm, const double *in, double *out, int n, int op)
{
  return MPI_Allreduce(in, out, n, MPI_DOUBLE, op_of(op), comm);
}

int signorini_allreduce_i64(MPI_Comm comm, const long long *in, long long *out, int n, int op)
{
  return MPI_Allreduce(in, out, n, MPI_LONG_LONG, op_of(op), comm);
}

int signorini_bcast_bytes(MPI_Comm comm, void *buf, int n, int root)
{
  return MPI_Bcast(buf, n, MPI_BYTE, root, comm);
}

#include <time.h>
/* MPI_Bcast that waits without spinning: MPI_Ibcast, then MPI_Test every `sleep_us`
 * microseconds (Open MPI's blocking collectives poll and keep a core busy while they wait,
 * which on a shared machine takes that core from the rank doing the work). */
int signorini_bcast_bytes_sleeping(MPI_Comm comm, void *buf, int n, int root, int sleep_us)
{
  MPI_Request request;
  int done = 0, code = MPI_Ibcast(buf, n, MPI_BYTE, root, comm, &request);
  if (code != MPI_SUCCESS) return code;
  while (!done) {
    code = MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (code != MPI_SUCCESS) return code;
    if (!done) {
      struct timespec pause = {0, (long)sleep_us * 1000L};
      nanosleep(&pause, NULL);
    }
  }
  return MPI_SUCCESS;
}

PetscReal signorini_petsc_infinity(void) { return PETSC_INFINITY; }

PetscBool signorini_mpi_initialized(void)
{
  int flag = 0;
  MPI_Initialized(&flag);
  return flag ? PETSC_TRUE : PETSC_FALSE;
}

#include <malloc.h>
/* Return freed heap memory to the operating system (glibc), so that resident-memory
 * measurements of a later phase are not hidden by memory an earlier phase freed. */
int signorini_release_free_memory(void) { return malloc_trim(0); }

#include <signal.h>
/* Ignore SIGXFSZ (file size limit exceeded, `ulimit -f`), whose default action kills the
 * process in the middle of a write: ignored, the write fails with EFBIG instead and the
 * program removes its partial file and says why. Returns 0, or -1 if signal() failed. */
int signorini_ignore_file_size_signal(void)
{
  return signal(SIGXFSZ, SIG_IGN) == SIG_ERR ? -1 : 0;
}
