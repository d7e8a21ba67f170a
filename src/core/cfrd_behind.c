/*
 * One job at a time on a second thread, behind the caller (docs/performance.md (ag)): the
 * results of stage k are written while stage k+1 is solved.
 *
 * cfrd_behind_post(job) waits for the job posted before it, then hands `job` to the
 * thread and returns at once; cfrd_behind_wait() returns when no job is pending or
 * running. So at most one job runs behind the caller, and jobs run in the order posted.
 * Everything a job reads or writes must be left alone by the caller from its post to the
 * next post or wait: the caller hands over a copy (cfrd_stage_writer).
 *
 * The thread is started by the first post. It blocks every signal, so that SIGINT and
 * SIGTERM reach the caller's thread, whose handler records them (cfrd_signals). Where it
 * cannot be started, or CFRD_WRITE_BEHIND=0 is set (a measuring aid), cfrd_behind_post runs
 * the job itself before it returns: the same work in the same order, on the caller's
 * thread. The thread is never joined: it waits, idle, for the next job until the process
 * exits, and every caller waits for its last job before the process ends.
 */
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>

typedef void (*cfrd_job_t)(void);

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t changed = PTHREAD_COND_INITIALIZER;
static cfrd_job_t job;          /* the job posted, not yet taken by the thread */
static int busy;                /* a job is posted or running */
static int state;               /* 0 not started, 1 running, -1 jobs run by the caller */
static long jobs_behind;        /* jobs run on the thread so far */

static void *worker(void *unused)
{
    (void)unused;
    pthread_mutex_lock(&lock);
    for (;;) {
        while (job == NULL) pthread_cond_wait(&changed, &lock);
        cfrd_job_t run = job;
        job = NULL;
        pthread_mutex_unlock(&lock);
        run();
        pthread_mutex_lock(&lock);
        jobs_behind++;
        busy = 0;
        pthread_cond_broadcast(&changed);
    }
    return NULL;
}

/* Start the thread, with every signal blocked in it; state -1 where it is not started. */
static void start(void)
{
    const char *setting = getenv("CFRD_WRITE_BEHIND");
    if (setting != NULL && strcmp(setting, "0") == 0) {
        state = -1;
        return;
    }
    sigset_t all, before;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &before);
    pthread_t thread;
    int status = pthread_create(&thread, NULL, worker, NULL);
    pthread_sigmask(SIG_SETMASK, &before, NULL);
    if (status != 0) {
        state = -1;
        return;
    }
    pthread_detach(thread);
    state = 1;
}

void cfrd_behind_wait(void)
{
    pthread_mutex_lock(&lock);
    while (busy) pthread_cond_wait(&changed, &lock);
    pthread_mutex_unlock(&lock);
}

void cfrd_behind_post(cfrd_job_t next)
{
    pthread_mutex_lock(&lock);
    while (busy) pthread_cond_wait(&changed, &lock);
    if (state == 0) start();
    if (state < 0) {
        pthread_mutex_unlock(&lock);
        next();
        return;
    }
    job = next;
    busy = 1;
    pthread_cond_broadcast(&changed);
    pthread_mutex_unlock(&lock);
}

/* The jobs run on the thread so far (0 where the caller runs them). */
long cfrd_behind_jobs(void)
{
    pthread_mutex_lock(&lock);
    long n = jobs_behind;
    pthread_mutex_unlock(&lock);
    return n;
}
