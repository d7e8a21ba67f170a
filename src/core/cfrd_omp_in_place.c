/* One-thread OpenMP parallel regions run in place, without a team (issue 21;
 * docs/performance.md (ae)).
 *
 * GCC compiles a `parallel` construct (and a combined `parallel for` of static schedule)
 * into a call of libgomp's GOMP_parallel(fn, data, num_threads, flags): libgomp resolves
 * the team's size, starts the team, runs fn(data) on the calling thread and, at the
 * region's end, passes the team's final barrier, which wakes the barrier's waiters by a
 * futex system call (FUTEX_WAKE, all waiters) even when the team is the caller alone.
 * CHOLMOD's supernodal factorisation (SuiteSparse 5, Debian's build with OpenMP) opens
 * several small parallel loops per supernode; cfrd runs them on one thread
 * (cfrd_omp_threads, begin_serial_library), and each still cost a team and a system call:
 * 1.1 million regions, about 0.25 s of system time, in a 5 s x4 bonded history.
 *
 * This definition of GOMP_parallel in the program takes the place of libgomp's for every
 * caller in the process (the program's own objects, the static SuiteSparse archives and the
 * shared libraries alike: the program's definition comes first in symbol lookup). When the
 * region would get one thread, it calls fn(data) directly; otherwise it hands the region to
 * libgomp's GOMP_parallel, found by dlsym(RTLD_NEXT). A region gets one thread when no
 * parallel region encloses it (omp_get_level() = 0) and either the construct asks for one
 * thread (num_threads 1, which is also what GCC passes when an `if` clause is false), or no
 * active level is allowed (max-active-levels 0, begin_serial_library), or the construct
 * names no count and the nthreads ICV is 1 (omp_get_max_threads(), cfrd's default).
 *
 * Run in place, the region's constructs behave as in a team of one: omp_get_thread_num()
 * is 0 and omp_get_num_threads() 1; worksharing loops, single and barriers are libgomp's
 * orphaned forms (no team: the calling thread does every iteration, a barrier returns at
 * once); reductions and critical sections are the same code on one thread. The same
 * iterations run in the same order on the same thread, so the results are the same bits.
 * What differs: omp_get_level() and omp_in_parallel() inside the region report 0 and false
 * (no caller in cfrd or SuiteSparse reads them), and an ICV set inside the region
 * (omp_set_num_threads) would outlive it (none is set there). Regions nested in a team's
 * region (omp_get_level() > 0) always go to libgomp, where worksharing binds to the
 * innermost team.
 *
 * GOMP_parallel is the entry point of GCC's OpenMP ABI since GCC 4.9 (libgomp's
 * GOMP_4.0 symbol version), unchanged since. Should libgomp's symbol not be found, a region
 * runs in place on one thread: the same results, without the threads.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <omp.h>
#include <stddef.h>

/* Weak: a program linked without libgomp has no OpenMP code, so never calls GOMP_parallel,
 * and links all the same. */
#pragma weak omp_get_level
#pragma weak omp_get_max_active_levels
#pragma weak omp_get_max_threads

typedef void (*parallel_entry_t)(void (*)(void *), void *, unsigned, unsigned);

static parallel_entry_t libgomp_parallel = NULL;
static unsigned long long regions_in_place = 0;

void GOMP_parallel(void (*fn)(void *), void *data, unsigned num_threads, unsigned flags)
{
    if (omp_get_level() == 0 &&
        (num_threads == 1 || omp_get_max_active_levels() == 0 ||
         (num_threads == 0 && omp_get_max_threads() == 1))) {
        regions_in_place++;   /* a plain count, read by the tests */
        fn(data);
        return;
    }
    parallel_entry_t entry = __atomic_load_n(&libgomp_parallel, __ATOMIC_ACQUIRE);
    if (entry == NULL) {
        entry = (parallel_entry_t)dlsym(RTLD_NEXT, "GOMP_parallel");
        if (entry == NULL) {
            fn(data);
            return;
        }
        __atomic_store_n(&libgomp_parallel, entry, __ATOMIC_RELEASE);
    }
    entry(fn, data, num_threads, flags);
}

/* The number of regions run in place so far (for the tests). */
unsigned long long cfrd_omp_regions_in_place(void)
{
    return regions_in_place;
}
