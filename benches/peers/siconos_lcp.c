/* Siconos' side of the LCP peer benchmark (benches/peers/run.sh): reads dense Siconos .dat
 * files and times Siconos' lexicographic Lemke, lcp_lexicolemke (libsiconos-numerics-dev),
 * exactly as crates/hopsim-lcp/examples/peer_lcp.rs times hopsim's LemkeSolver:
 *
 *     siconos_lcp [--batches K] [--batch-us U] FILE...
 *
 * Per file: one untimed solve (warm-up, and its z for the cross-check), then a batch size N
 * chosen by doubling until one batch takes at least U us (default 200), then K batches
 * (default 31) of N solves; the result is the median over the batches of the batch time
 * divided by N. The problem and SolverOptions are built once and reused; z and w are
 * preallocated. Prints one JSON object per file and line:
 * {"file", "n", "status", "pivots", "median_ns", "batch", "batches", "z"}.
 *
 * The .dat reader is our own (the format of crates/hopsim-lcp/src/dat.rs: n, storage flag 0,
 * rows, cols, rows cols, M row by row, q, free-text comment), so both sides read the same
 * numbers regardless of the Siconos version's reader.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "LCP_Solvers.h"
#include "LinearComplementarityProblem.h"
#include "NumericsMatrix.h"
#include "SolverOptions.h"
#include "lcp_cst.h"

static double now_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Reads a dense .dat file: M column-major (for NM_DENSE) and q, both malloc'ed. */
static int read_dat(const char *path, int *n_out, double **m_out, double **q_out) {
  FILE *f = fopen(path, "r");
  if (!f) {
    fprintf(stderr, "error: %s: cannot open: %s\n", path, strerror(errno));
    return -1;
  }
  int n, storage, r1, c1, r2, c2;
  if (fscanf(f, "%d %d %d %d %d %d", &n, &storage, &r1, &c1, &r2, &c2) != 6 || n <= 0 ||
      storage != 0 || r1 != n || c1 != n || r2 != n || c2 != n) {
    fprintf(stderr, "error: %s: bad header (expected: n, 0, n, n, n n)\n", path);
    fclose(f);
    return -1;
  }
  double *m = malloc(sizeof(double) * (size_t)n * (size_t)n);
  double *q = malloc(sizeof(double) * (size_t)n);
  if (!m || !q) {
    fprintf(stderr, "error: out of memory\n");
    fclose(f);
    return -1;
  }
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++)
      if (fscanf(f, "%lf", &m[i + j * n]) != 1) {
        fprintf(stderr, "error: %s: expected %d matrix entries\n", path, n * n);
        fclose(f);
        return -1;
      }
  for (int i = 0; i < n; i++)
    if (fscanf(f, "%lf", &q[i]) != 1) {
      fprintf(stderr, "error: %s: expected %d entries of q\n", path, n);
      fclose(f);
      return -1;
    }
  fclose(f);
  *n_out = n;
  *m_out = m;
  *q_out = q;
  return 0;
}

static int usage(void) {
  fprintf(stderr, "usage: siconos_lcp [--batches K] [--batch-us U] FILE...\n");
  return 2;
}

int main(int argc, char **argv) {
  int batches = 31;
  double batch_us = 200.0;
  int first_file = argc;
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "--batches") == 0 && i + 1 < argc) {
      batches = atoi(argv[++i]);
      if (batches <= 0) return usage();
    } else if (strcmp(argv[i], "--batch-us") == 0 && i + 1 < argc) {
      batch_us = atof(argv[++i]);
      if (!(batch_us > 0)) return usage();
    } else if (argv[i][0] == '-') {
      return usage();
    } else {
      first_file = i;
      break;
    }
  }
  if (first_file >= argc) return usage();

  SolverOptions *options = solver_options_create(SICONOS_LCP_LEMKE);
  if (!options) {
    fprintf(stderr, "error: solver_options_create(SICONOS_LCP_LEMKE) failed\n");
    return 1;
  }
  double *times = malloc(sizeof(double) * (size_t)batches);
  for (int a = first_file; a < argc; a++) {
    const char *path = argv[a];
    int n;
    double *m, *q;
    if (read_dat(path, &n, &m, &q) != 0) return 1;
    LinearComplementarityProblem *problem = newLCP();
    problem->size = n;
    problem->M = NM_create_from_data(NM_DENSE, n, n, m); /* takes ownership of m */
    problem->q = q;
    double *z = calloc((size_t)n, sizeof(double));
    double *w = calloc((size_t)n, sizeof(double));
    int info = -1;

    lcp_lexicolemke(problem, z, w, &info, options);
    int status = info;
    int pivots = options->iparam[SICONOS_IPARAM_ITER_DONE];
    double *z_first = malloc(sizeof(double) * (size_t)n);
    memcpy(z_first, z, sizeof(double) * (size_t)n);

    long batch = 1;
    for (;;) {
      double t0 = now_ns();
      for (long k = 0; k < batch; k++) lcp_lexicolemke(problem, z, w, &info, options);
      if (now_ns() - t0 >= batch_us * 1e3 || batch >= (1L << 30)) break;
      batch *= 2;
    }
    for (int b = 0; b < batches; b++) {
      double t0 = now_ns();
      for (long k = 0; k < batch; k++) lcp_lexicolemke(problem, z, w, &info, options);
      times[b] = (now_ns() - t0) / (double)batch;
    }
    qsort(times, (size_t)batches, sizeof(double), cmp_double);
    double median = batches % 2 ? times[batches / 2]
                                : 0.5 * (times[batches / 2 - 1] + times[batches / 2]);

    printf("{\"file\": \"%s\", \"n\": %d, \"status\": \"%s\", \"info\": %d, \"pivots\": %d, "
           "\"median_ns\": %.2f, \"batch\": %ld, \"batches\": %d, \"z\": [",
           path, n, status == 0 ? "solved" : "failed", status, pivots, median, batch, batches);
    for (int i = 0; i < n; i++) printf("%s%.17g", i ? ", " : "", z_first[i]);
    printf("]}\n");
    fflush(stdout);

    free(z_first);
    free(z);
    free(w);
    freeLinearComplementarityProblem(problem); /* frees M (and m) and q */
  }
  free(times);
  solver_options_delete(options);
  return 0;
}
