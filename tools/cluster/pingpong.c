/* MPI ping-pong between ranks 0 and 1: the latency and bandwidth inputs of
 * tools/cost_model.py. Build and run (tools/cost_model.py does this itself):
 *   mpicc -O2 -o pingpong tools/cluster/pingpong.c
 *   mpirun -n 2 ./pingpong
 * Prints one line per message size: "bytes seconds_per_one_way_message" (median of
 * 7 repetitions of a burst of round trips), for sizes 8 B .. 16 MiB. */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>

static int compare(const void *a, const void *b)
{
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);
  int rank, size;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size < 2)
    {
      if (rank == 0)
        fprintf(stderr, "pingpong: needs 2 ranks\n");
      MPI_Finalize();
      return 1;
    }
  const long max_bytes = 16L << 20;
  char      *buffer    = malloc(max_bytes);
  for (long i = 0; i < max_bytes; ++i)
    buffer[i] = (char)i;
  for (long bytes = 8; bytes <= max_bytes; bytes *= 4)
    {
      const int trips = bytes < 65536 ? 1000 : (bytes < (1L << 20) ? 100 : 10);
      double    t[7];
      for (int rep = 0; rep < 7; ++rep)
        {
          MPI_Barrier(MPI_COMM_WORLD);
          const double start = MPI_Wtime();
          for (int k = 0; k < trips; ++k)
            if (rank == 0)
              {
                MPI_Send(buffer, (int)bytes, MPI_CHAR, 1, 0, MPI_COMM_WORLD);
                MPI_Recv(buffer, (int)bytes, MPI_CHAR, 1, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
              }
            else if (rank == 1)
              {
                MPI_Recv(buffer, (int)bytes, MPI_CHAR, 0, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
                MPI_Send(buffer, (int)bytes, MPI_CHAR, 0, 0, MPI_COMM_WORLD);
              }
          t[rep] = (MPI_Wtime() - start) / (2.0 * trips);
        }
      qsort(t, 7, sizeof(double), compare);
      if (rank == 0)
        printf("%ld %.9e\n", bytes, t[3]);
    }
  free(buffer);
  MPI_Finalize();
  return 0;
}
