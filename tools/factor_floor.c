/* The numeric factorisation floor (issue 21; docs/performance.md, "(k)").
 *
 *     tools/factor_floor [--no-scale] [--repeat N] MATRIX.mtx
 *     make floor MTX=MATRIX.mtx
 *
 * Reads a matrix cfrd wrote (CFRD_WRITE_MATRIX, Matrix Market coordinate, general) and times,
 * best of N (default 5), on that same matrix:
 *   - UMFPACK as cfrd calls it (symmetric strategy, AMD ordering, row scaling by the sum of
 *     magnitudes unless --no-scale, as cfrd's contact systems): the numeric factorisation
 *     (umfpack_di_numeric with one kept symbolic analysis) and one solve; then the same with
 *     UMFPACK's METIS ordering (a measurement only: cfrd orders by AMD);
 *   - CHOLMOD supernodal LL^T of the upper triangle (the matrix is checked symmetric first)
 *     with each of the AMD, METIS and NESDIS orderings: cholmod_factorize with one kept
 *     analysis, and one solve.
 * The first, mean and best of the N times are printed (the first numeric factorisation
 * touches fresh memory, as cfrd's first of a new pattern does). UMFPACK's solve is timed with
 * its default two steps of iterative refinement (as cfrd solves) and with none.
 * Every solve's relative residual |b - A x|_inf / |b|_inf and its error max |x - 1| are
 * printed (b = A * ones: the exact solution is ones), so a time comes with the proof that
 * the solution is one. Wall time (CLOCK_MONOTONIC); the BLAS
 * threads are whatever the environment gives (make floor sets OPENBLAS_NUM_THREADS=1, as
 * cfrd runs). A matrix that is not symmetric positive definite gets UMFPACK's times only.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <suitesparse/cholmod.h>
#include <suitesparse/umfpack.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* First, mean and best of the times of one step repeated. */
typedef struct { double first, sum, best; int count; } times_t;

static void add_time(times_t *t, double seconds)
{
    if (t->count == 0) { t->first = seconds; t->best = seconds; }
    if (seconds < t->best) t->best = seconds;
    t->sum += seconds;
    t->count++;
}

static void print_times(const char *what, const times_t *t)
{
    printf("  %-22s best %8.4f s  first %8.4f s  mean %8.4f s\n", what, t->best, t->first,
           t->sum / t->count);
}

/* |b - A x|_inf / |b|_inf for the full (unsymmetric-stored) matrix A in CSC form. */
static double residual(int n, const int *ap, const int *ai, const double *ax, const double *x,
                       const double *b)
{
    double *r = malloc(sizeof(double) * (size_t)n);
    double rmax = 0.0, bmax = 0.0;
    for (int i = 0; i < n; i++) r[i] = b[i];
    for (int j = 0; j < n; j++)
        for (int p = ap[j]; p < ap[j + 1]; p++) r[ai[p]] -= ax[p] * x[j];
    for (int i = 0; i < n; i++) {
        if (fabs(r[i]) > rmax) rmax = fabs(r[i]);
        if (fabs(b[i]) > bmax) bmax = fabs(b[i]);
    }
    free(r);
    return rmax / bmax;
}

/* max |x_i - 1|: b = A * ones, so the exact solution is ones. */
static double error_ones(int n, const double *x)
{
    double e = 0.0;
    for (int i = 0; i < n; i++)
        if (fabs(x[i] - 1.0) > e) e = fabs(x[i] - 1.0);
    return e;
}

/* Largest |a_ij - a_ji| / max|a|; the matrix must be packed with sorted columns. */
static double asymmetry(cholmod_sparse *a, cholmod_common *c)
{
    cholmod_sparse *t = cholmod_transpose(a, 1, c);
    const int *ap = a->p, *ai = a->i, *tp = t->p, *ti = t->i;
    const double *ax = a->x, *tx = t->x;
    double dmax = 0.0, amax = 0.0;
    int n = (int)a->ncol, pattern_differs = 0;
    for (int j = 0; j < n; j++) {
        if (ap[j + 1] - ap[j] != tp[j + 1] - tp[j]) { pattern_differs = 1; break; }
        for (int p = ap[j]; p < ap[j + 1]; p++) {
            if (ai[p] != ti[p]) { pattern_differs = 1; break; }
            if (fabs(ax[p] - tx[p]) > dmax) dmax = fabs(ax[p] - tx[p]);
            if (fabs(ax[p]) > amax) amax = fabs(ax[p]);
        }
    }
    cholmod_free_sparse(&t, c);
    return pattern_differs ? INFINITY : dmax / amax;
}

static void umfpack_times(cholmod_sparse *a, int scale, int ordering, const char *name,
                          int repeat, const double *b)
{
    int n = (int)a->nrow, *ap = a->p, *ai = a->i;
    double *ax = a->x, control[UMFPACK_CONTROL], info[UMFPACK_INFO];
    double *x = malloc(sizeof(double) * (size_t)n), *x0 = malloc(sizeof(double) * (size_t)n);
    times_t t_num = {0}, t_solve = {0}, t_solve0 = {0};
    double t0, lnz, unz, flops;
    void *symbolic = NULL, *numeric = NULL;
    int status;
    umfpack_di_defaults(control);
    control[UMFPACK_PRL] = 0;
    control[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_SYMMETRIC;
    control[UMFPACK_ORDERING] = ordering;
    control[UMFPACK_SCALE] = scale ? UMFPACK_SCALE_SUM : UMFPACK_SCALE_NONE;
    t0 = now();
    status = umfpack_di_symbolic(n, n, ap, ai, ax, &symbolic, control, info);
    printf("UMFPACK  symmetric strategy, %s, scale %s: symbolic %.3f s\n", name,
           scale ? "sum" : "none", now() - t0);
    if (status != UMFPACK_OK) { printf("  symbolic failed: status %d\n", status); return; }
    for (int k = 0; k < repeat; k++) {
        if (numeric) umfpack_di_free_numeric(&numeric);
        t0 = now();
        status = umfpack_di_numeric(ap, ai, ax, symbolic, &numeric, control, info);
        add_time(&t_num, now() - t0);
        if (status != UMFPACK_OK) { printf("  numeric failed: status %d\n", status); return; }
    }
    lnz = info[UMFPACK_LNZ];
    unz = info[UMFPACK_UNZ];
    flops = info[UMFPACK_FLOPS];
    for (int k = 0; k < repeat; k++) {      /* UMFPACK's default: 2 refinement steps */
        t0 = now();
        umfpack_di_solve(UMFPACK_A, ap, ai, ax, x, b, numeric, control, info);
        add_time(&t_solve, now() - t0);
    }
    control[UMFPACK_IRSTEP] = 0;
    for (int k = 0; k < repeat; k++) {
        t0 = now();
        umfpack_di_solve(UMFPACK_A, ap, ai, ax, x0, b, numeric, control, info);
        add_time(&t_solve0, now() - t0);
    }
    printf("  L+U nnz %.3e  flops %.3e  residual %.1e (refined), %.1e (not)  "
           "max|x - 1| %.1e\n", lnz + unz - n, flops, residual(n, ap, ai, ax, x, b),
           residual(n, ap, ai, ax, x0, b), error_ones(n, x));
    print_times("numeric", &t_num);
    print_times("solve (IRSTEP 2)", &t_solve);
    print_times("solve (IRSTEP 0)", &t_solve0);
    umfpack_di_free_numeric(&numeric);
    umfpack_di_free_symbolic(&symbolic);
    free(x);
    free(x0);
}

static void cholmod_times(cholmod_sparse *a, cholmod_sparse *upper, int ordering,
                          const char *name, int repeat, cholmod_dense *b, cholmod_common *c)
{
    times_t t_num = {0}, t_solve = {0};
    double t0, t_an, lnz, flops;
    cholmod_dense *x = NULL;
    c->nmethods = 1;
    c->method[0].ordering = ordering;
    c->postorder = 1;
    c->supernodal = CHOLMOD_SUPERNODAL;
    t0 = now();
    cholmod_factor *l = cholmod_analyze(upper, c);
    t_an = now() - t0;
    if (l == NULL || c->status != CHOLMOD_OK) {
        printf("CHOLMOD  supernodal, %s: analyse failed (status %d)\n", name, c->status);
        if (l) cholmod_free_factor(&l, c);
        return;
    }
    for (int k = 0; k < repeat; k++) {
        t0 = now();
        cholmod_factorize(upper, l, c);
        add_time(&t_num, now() - t0);
        if (c->status != CHOLMOD_OK) {
            printf("CHOLMOD  supernodal, %s: not positive definite (column %d)\n", name,
                   (int)l->minor);
            cholmod_free_factor(&l, c);
            return;
        }
    }
    lnz = c->lnz;
    flops = c->fl;
    for (int k = 0; k < repeat; k++) {
        if (x) cholmod_free_dense(&x, c);
        t0 = now();
        x = cholmod_solve(CHOLMOD_A, l, b, c);
        add_time(&t_solve, now() - t0);
    }
    printf("CHOLMOD  supernodal, %s: analyse %.3f s\n", name, t_an);
    printf("  L nnz   %.3e  flops %.3e  residual %.1e  max|x - 1| %.1e\n", lnz, flops,
           residual((int)a->ncol, a->p, a->i, a->x, x->x, b->x),
           error_ones((int)a->ncol, x->x));
    print_times("numeric", &t_num);
    print_times("solve", &t_solve);
    cholmod_free_dense(&x, c);
    cholmod_free_factor(&l, c);
}

int main(int argc, char **argv)
{
    int scale = 1, repeat = 5;
    const char *path = NULL;
    for (int k = 1; k < argc; k++) {
        if (strcmp(argv[k], "--no-scale") == 0) scale = 0;
        else if (strcmp(argv[k], "--repeat") == 0 && k + 1 < argc) repeat = atoi(argv[++k]);
        else path = argv[k];
    }
    if (path == NULL || repeat < 1) {
        fprintf(stderr, "usage: factor_floor [--no-scale] [--repeat N] MATRIX.mtx\n");
        return 2;
    }
    FILE *f = fopen(path, "r");
    if (f == NULL) { fprintf(stderr, "factor_floor: cannot read %s\n", path); return 2; }
    cholmod_common common, *c = &common;
    cholmod_start(c);
    c->print = 0;
    double t0 = now();
    cholmod_sparse *a = cholmod_read_sparse(f, c);
    fclose(f);
    if (a == NULL) {
        fprintf(stderr, "factor_floor: %s is no Matrix Market matrix\n", path);
        return 2;
    }
    /* a "general" file is read unsymmetric; sort and pack it (and drop nothing) */
    cholmod_sort(a, c);
    int n = (int)a->nrow;
    printf("%s: n %d, nnz %ld, read in %.2f s\n", path, n, (long)cholmod_nnz(a, c), now() - t0);
    /* b = A * ones, for the residuals */
    cholmod_dense *ones = cholmod_ones(n, 1, CHOLMOD_REAL, c);
    cholmod_dense *b = cholmod_zeros(n, 1, CHOLMOD_REAL, c);
    double alpha[2] = {1, 0}, beta[2] = {0, 0};
    cholmod_sdmult(a, 0, alpha, beta, ones, b, c);
    umfpack_times(a, scale, UMFPACK_ORDERING_AMD, "AMD (as cfrd)", repeat, b->x);
    umfpack_times(a, scale, UMFPACK_ORDERING_METIS, "METIS", repeat, b->x);
    double asym = asymmetry(a, c);
    printf("asymmetry max|a_ij - a_ji| / max|a| = %.1e\n", asym);
    if (asym <= 1e-12) {
        cholmod_sparse *upper = cholmod_copy(a, 1, 1, c);
        cholmod_times(a, upper, CHOLMOD_AMD, "AMD", repeat, b, c);
        cholmod_times(a, upper, CHOLMOD_METIS, "METIS", repeat, b, c);
        cholmod_times(a, upper, CHOLMOD_NESDIS, "NESDIS", repeat, b, c);
        cholmod_free_sparse(&upper, c);
    } else {
        printf("CHOLMOD  not tried: the matrix is not symmetric\n");
    }
    cholmod_free_dense(&ones, c);
    cholmod_free_dense(&b, c);
    cholmod_free_sparse(&a, c);
    cholmod_finish(c);
    return 0;
}
