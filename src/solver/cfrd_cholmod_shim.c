/* CHOLMOD (SuiteSparse) behind a few plain C functions for cfrd_cholmod.f90 (issue 21).
 *
 * cholmod_common and cholmod_factor are C structs whose layout changes between CHOLMOD
 * versions; binding them field by field from Fortran would break silently with the next
 * SuiteSparse. This file owns them: Fortran sees an opaque handle, int and double arrays
 * and int status codes only. No logic beyond the calls: the symmetry check, the upper
 * triangle and the fallback to UMFPACK are in Fortran.
 *
 * The matrix is the upper triangle in compressed columns, 0-based, rows sorted in each
 * column (stype 1: CHOLMOD reads the upper part as the whole symmetric matrix).
 */
#include <stdlib.h>
#include <string.h>

#include <suitesparse/cholmod.h>
#include <suitesparse/cholmod_camd.h>

typedef struct {
    cholmod_common common;
    cholmod_sparse *a;   /* the upper triangle, values of the last factorisation */
    cholmod_factor *l;   /* symbolic, then numeric (supernodal LL^T) */
    cholmod_dense *x, *y, *e;   /* cholmod_solve2's reused workspace */
    cholmod_dense *b;           /* the half solves' right-hand side (cfrd_cholmod_forward) */
} cfrd_cholmod_t;

void cfrd_cholmod_free(void *handle);

/* A new handle with one ordering (2 AMD, 3 METIS, 4 NESDIS: CHOLMOD's codes), supernodal,
 * silent; NULL when out of memory. */
void *cfrd_cholmod_new(int ordering)
{
    cfrd_cholmod_t *h = calloc(1, sizeof(cfrd_cholmod_t));
    if (h == NULL) return NULL;
    cholmod_start(&h->common);
    h->common.nmethods = 1;
    h->common.method[0].ordering = ordering;
    h->common.postorder = 1;
    h->common.supernodal = CHOLMOD_SUPERNODAL;
    h->common.print = 0;
    /* a matrix that is not positive definite goes to UMFPACK: no need to finish */
    h->common.quick_return_if_not_posdef = 1;
    return h;
}

static void free_factor(cfrd_cholmod_t *h)
{
    if (h->l) cholmod_free_factor(&h->l, &h->common);
    if (h->a) cholmod_free_sparse(&h->a, &h->common);
    if (h->x) cholmod_free_dense(&h->x, &h->common);
    if (h->y) cholmod_free_dense(&h->y, &h->common);
    if (h->e) cholmod_free_dense(&h->e, &h->common);
    if (h->b) cholmod_free_dense(&h->b, &h->common);
}

/* The pattern ap, ai (n columns, values 0) as the handle's matrix, replacing an earlier
 * analysis. Returns CHOLMOD's status. */
static int load_pattern(cfrd_cholmod_t *h, int n, const int *ap, const int *ai)
{
    int nnz = ap[n];
    free_factor(h);
    h->common.status = CHOLMOD_OK;
    h->a = cholmod_allocate_sparse((size_t)n, (size_t)n, (size_t)nnz, 1, 1, 1, CHOLMOD_REAL,
                                   &h->common);
    if (h->a == NULL) return h->common.status < 0 ? h->common.status : CHOLMOD_OUT_OF_MEMORY;
    memcpy(h->a->p, ap, sizeof(int) * (size_t)(n + 1));
    memcpy(h->a->i, ai, sizeof(int) * (size_t)nnz);
    memset(h->a->x, 0, sizeof(double) * (size_t)nnz);
    return CHOLMOD_OK;
}

/* Symbolic analysis (ordering, supernodes) of the pattern ap, ai (n columns); replaces an
 * earlier one. Returns CHOLMOD's status (0 ok, negative an error). */
int cfrd_cholmod_analyse(void *handle, int n, const int *ap, const int *ai)
{
    cfrd_cholmod_t *h = handle;
    int status = load_pattern(h, n, ap, ai);
    if (status != CHOLMOD_OK) return status;
    h->l = cholmod_analyze(h->a, &h->common);
    if (h->l == NULL) return h->common.status < 0 ? h->common.status : CHOLMOD_INVALID;
    return h->common.status < 0 ? h->common.status : CHOLMOD_OK;
}

/* Symbolic analysis as cfrd_cholmod_analyse, with the columns where last[j] != 0 ordered
 * after all the others (the contact systems' coupled dofs, cfrd_schur.f90): CAMD's
 * constrained minimum degree orders each set, and the analysis keeps that order (no
 * postordering, which could interleave the last set with the rest). */
int cfrd_cholmod_analyse_last(void *handle, int n, const int *ap, const int *ai,
                              const int *last)
{
    cfrd_cholmod_t *h = handle;
    int *cmember, *perm, ok, status = load_pattern(h, n, ap, ai);
    if (status != CHOLMOD_OK) return status;
    cmember = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
    perm = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
    if (cmember == NULL || perm == NULL) {
        free(cmember);
        free(perm);
        return CHOLMOD_OUT_OF_MEMORY;
    }
    for (int j = 0; j < n; j++) cmember[j] = last[j] != 0;
    ok = cholmod_camd(h->a, NULL, 0, cmember, perm, &h->common);
    if (ok) {
        h->common.nmethods = 1;
        h->common.method[0].ordering = CHOLMOD_GIVEN;
        h->common.postorder = 0;
        h->l = cholmod_analyze_p(h->a, perm, NULL, 0, &h->common);
    }
    free(cmember);
    free(perm);
    if (!ok || h->l == NULL) return h->common.status < 0 ? h->common.status : CHOLMOD_INVALID;
    return h->common.status < 0 ? h->common.status : CHOLMOD_OK;
}

/* The factor's permutation (perm[k] = the column of A in position k, 0-based). Returns
 * -100 without an analysis. */
int cfrd_cholmod_permutation(void *handle, int *perm)
{
    cfrd_cholmod_t *h = handle;
    if (h->l == NULL) return -100;
    memcpy(perm, h->l->Perm, sizeof(int) * h->l->n);
    return CHOLMOD_OK;
}

/* The last `tail` columns of the supernodal factor L (positions n - tail to n - 1, whose
 * rows are all in the tail too) as a dense lower triangle, column-major, leading dimension
 * tail; and the smallest and largest L_jj^2 of the other columns (0 and 0 when there are
 * none). Returns -100 without a numeric supernodal LL^T factor. */
int cfrd_cholmod_tail(void *handle, int tail, double *g, double *pivots)
{
    cfrd_cholmod_t *h = handle;
    cholmod_factor *l = h->l;
    int n, n0, *super, *lpi, *lpx, *ls;
    double *lx, lo = 0.0, hi = 0.0;
    if (l == NULL || !l->is_super || !l->is_ll || l->xtype != CHOLMOD_REAL) return -100;
    n = (int)l->n;
    n0 = n - tail;
    super = l->super;
    lpi = l->pi;
    lpx = l->px;
    ls = l->s;
    lx = l->x;
    memset(g, 0, sizeof(double) * (size_t)tail * (size_t)tail);
    for (size_t s = 0; s < l->nsuper; s++) {
        int k1 = super[s], k2 = super[s + 1], nsrow = lpi[s + 1] - lpi[s];
        for (int k = k1; k < k2; k++) {
            const double *column = lx + lpx[s] + (size_t)(k - k1) * (size_t)nsrow;
            if (k < n0) {
                double d = column[k - k1] * column[k - k1];
                if (k == 0 || d < lo) lo = d;
                if (k == 0 || d > hi) hi = d;
                continue;
            }
            for (int r = k - k1; r < nsrow; r++)
                g[(size_t)(k - n0) * (size_t)tail + (size_t)(ls[lpi[s] + r] - n0)] = column[r];
        }
    }
    pivots[0] = lo;
    pivots[1] = hi;
    return CHOLMOD_OK;
}

/* z = L^-1 P b (forward), or x = P^T L^-T z (backward): the two halves of a solve, in the
 * factor's own order between them. Returns CHOLMOD's status. */
static int half_solve(cfrd_cholmod_t *h, int backward, const double *in, double *out)
{
    cholmod_dense rhs;
    const int *perm;
    size_t n;
    if (h->l == NULL || !h->l->is_ll) return -100;
    n = h->l->n;
    perm = h->l->Perm;
    if (h->b == NULL || h->b->nrow != n) {
        if (h->b) cholmod_free_dense(&h->b, &h->common);
        h->b = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &h->common);
        if (h->b == NULL) return CHOLMOD_OUT_OF_MEMORY;
    }
    memset(&rhs, 0, sizeof(rhs));
    rhs.nrow = n;
    rhs.ncol = 1;
    rhs.nzmax = n;
    rhs.d = n;
    rhs.x = h->b->x;
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    if (!backward)
        for (size_t k = 0; k < n; k++) ((double *)rhs.x)[k] = in[perm[k]];
    else
        memcpy(rhs.x, in, sizeof(double) * n);
    h->common.status = CHOLMOD_OK;
    if (!cholmod_solve2(backward ? CHOLMOD_Lt : CHOLMOD_L, h->l, &rhs, NULL, &h->x, NULL,
                        &h->y, &h->e, &h->common))
        return h->common.status < 0 ? h->common.status : CHOLMOD_INVALID;
    if (!backward)
        memcpy(out, h->x->x, sizeof(double) * n);
    else
        for (size_t k = 0; k < n; k++) out[perm[k]] = ((double *)h->x->x)[k];
    return CHOLMOD_OK;
}

int cfrd_cholmod_forward(void *handle, const double *b, double *z)
{
    return half_solve(handle, 0, b, z);
}

int cfrd_cholmod_backward(void *handle, const double *z, double *x)
{
    return half_solve(handle, 1, z, x);
}

/* A new handle holding a copy of `from`'s analysis (its pattern and its factor, which a
 * numeric factorisation overwrites whole: the same as an analysis of the same pattern,
 * which depends on the pattern and the ordering alone). NULL when `from` has no analysis
 * or memory runs out. */
void *cfrd_cholmod_copy(void *from)
{
    cfrd_cholmod_t *f = from, *h;
    if (f == NULL || f->a == NULL || f->l == NULL) return NULL;
    h = cfrd_cholmod_new(f->common.method[0].ordering);
    if (h == NULL) return NULL;
    h->a = cholmod_copy_sparse(f->a, &h->common);
    if (h->a != NULL) h->l = cholmod_copy_factor(f->l, &h->common);
    if (h->a == NULL || h->l == NULL) {
        cfrd_cholmod_free(h);
        return NULL;
    }
    h->common.lnz = f->common.lnz;   /* the analysis's statistics (factor_nonzeros) */
    h->common.fl = f->common.fl;
    return h;
}

/* Numeric factorisation of the values ax (the analysed pattern's). Returns 0 ok, 1 not
 * positive definite (CHOLMOD_NOT_POSDEF), negative an error; -100 without an analysis. */
int cfrd_cholmod_factorise(void *handle, const double *ax)
{
    cfrd_cholmod_t *h = handle;
    if (h->a == NULL || h->l == NULL) return -100;
    memcpy(h->a->x, ax, sizeof(double) * (size_t)((int *)h->a->p)[h->a->ncol]);
    h->common.status = CHOLMOD_OK;
    cholmod_factorize(h->a, h->l, &h->common);
    if (h->common.status == CHOLMOD_OK && h->l->minor < h->l->n) return CHOLMOD_NOT_POSDEF;
    return h->common.status;
}

/* CHOLMOD's reciprocal condition estimate of the factor, (min L_jj / max L_jj)^2; 0 when
 * there is none. */
double cfrd_cholmod_rcond(void *handle)
{
    cfrd_cholmod_t *h = handle;
    if (h->l == NULL || !h->l->is_ll) return 0.0;
    return cholmod_rcond(h->l, &h->common);
}

/* Nonzeros of L (the diagonal counted) of the analysis. */
double cfrd_cholmod_factor_nonzeros(void *handle)
{
    cfrd_cholmod_t *h = handle;
    return h->l == NULL ? 0.0 : h->common.lnz;
}

/* x = A^-1 b with the factorisation (n = the analysed size). Returns CHOLMOD's status. */
int cfrd_cholmod_solve(void *handle, const double *b, double *x)
{
    cfrd_cholmod_t *h = handle;
    cholmod_dense rhs;
    if (h->l == NULL || !h->l->is_ll) return -100;
    memset(&rhs, 0, sizeof(rhs));
    rhs.nrow = h->l->n;
    rhs.ncol = 1;
    rhs.nzmax = h->l->n;
    rhs.d = h->l->n;
    rhs.x = (void *)b;
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    h->common.status = CHOLMOD_OK;
    if (!cholmod_solve2(CHOLMOD_A, h->l, &rhs, NULL, &h->x, NULL, &h->y, &h->e, &h->common))
        return h->common.status < 0 ? h->common.status : CHOLMOD_INVALID;
    memcpy(x, h->x->x, sizeof(double) * h->l->n);
    return CHOLMOD_OK;
}

/* Free everything (a NULL handle is fine). */
void cfrd_cholmod_free(void *handle)
{
    cfrd_cholmod_t *h = handle;
    if (h == NULL) return;
    free_factor(h);
    cholmod_finish(&h->common);
    free(h);
}
