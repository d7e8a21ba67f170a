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
 *
 * A second queue of the same kind, on a thread of its own, takes the jobs done ahead of the
 * caller (docs/performance.md (ak)): the next stage's equations, sparse pattern and symbolic
 * analysis, prepared while this stage is solved (cfrd_linear_system). cfrd_ahead_post
 * returns 0, and runs nothing, where such a job would not run beside the caller: one
 * processor online, no thread, or CFRD_AHEAD=0 (a measuring aid); the caller then does
 * the work itself when it needs it.
 */
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef void (*cfrd_job_t)(void);

/* One queue: at most one job posted or running, its own thread. */
struct queue {
    pthread_mutex_t lock;
    pthread_cond_t changed;
    cfrd_job_t job;    /* the job posted, not yet taken by the thread */
    int busy;          /* a job is posted or running */
    int state;         /* 0 not started, 1 running, -1 jobs run by the caller (or none) */
    long jobs_done;    /* jobs run on the thread so far */
};

static struct queue behind = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER,
                              NULL, 0, 0, 0};
static struct queue ahead = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER,
                             NULL, 0, 0, 0};

static void *worker(void *arg)
{
    struct queue *q = arg;
    pthread_mutex_lock(&q->lock);
    for (;;) {
        while (q->job == NULL) pthread_cond_wait(&q->changed, &q->lock);
        cfrd_job_t run = q->job;
        q->job = NULL;
        pthread_mutex_unlock(&q->lock);
        run();
        pthread_mutex_lock(&q->lock);
        q->jobs_done++;
        q->busy = 0;
        pthread_cond_broadcast(&q->changed);
    }
    return NULL;
}

/* Start the queue's thread, with every signal blocked in it, unless the environment
 * variable `off` is "0"; state -1 where it is not started. */
static void start(struct queue *q, const char *off)
{
    const char *setting = getenv(off);
    if (setting != NULL && strcmp(setting, "0") == 0) {
        q->state = -1;
        return;
    }
    sigset_t all, before;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &before);
    pthread_t thread;
    int status = pthread_create(&thread, NULL, worker, q);
    pthread_sigmask(SIG_SETMASK, &before, NULL);
    if (status != 0) {
        q->state = -1;
        return;
    }
    pthread_detach(thread);
    q->state = 1;
}

static void wait_idle(struct queue *q)
{
    pthread_mutex_lock(&q->lock);
    while (q->busy) pthread_cond_wait(&q->changed, &q->lock);
    pthread_mutex_unlock(&q->lock);
}

/* Hand `next` to the queue's thread (after the job before it); 0 when the queue has no
 * thread (the job is not run). */
static int hand_over(struct queue *q, cfrd_job_t next)
{
    pthread_mutex_lock(&q->lock);
    while (q->busy) pthread_cond_wait(&q->changed, &q->lock);
    if (q->state < 0) {
        pthread_mutex_unlock(&q->lock);
        return 0;
    }
    q->job = next;
    q->busy = 1;
    pthread_cond_broadcast(&q->changed);
    pthread_mutex_unlock(&q->lock);
    return 1;
}

void cfrd_behind_wait(void) { wait_idle(&behind); }

void cfrd_behind_post(cfrd_job_t next)
{
    pthread_mutex_lock(&behind.lock);
    if (behind.state == 0) start(&behind, "CFRD_WRITE_BEHIND");
    pthread_mutex_unlock(&behind.lock);
    if (!hand_over(&behind, next)) next();
}

/* The jobs run on the thread so far (0 where the caller runs them). */
long cfrd_behind_jobs(void)
{
    pthread_mutex_lock(&behind.lock);
    long n = behind.jobs_done;
    pthread_mutex_unlock(&behind.lock);
    return n;
}

/* Post a job to be done ahead of the caller; 1 when posted, 0 when it is not run at all. */
int cfrd_ahead_post(cfrd_job_t next)
{
    pthread_mutex_lock(&ahead.lock);
    if (ahead.state == 0) {
        if (sysconf(_SC_NPROCESSORS_ONLN) < 2)
            ahead.state = -1;
        else
            start(&ahead, "CFRD_AHEAD");
    }
    pthread_mutex_unlock(&ahead.lock);
    return hand_over(&ahead, next);
}

void cfrd_ahead_wait(void) { wait_idle(&ahead); }

/* The queue ahead has its thread (1), has none (0), or has had no post yet (-1). */
int cfrd_ahead_thread(void)
{
    pthread_mutex_lock(&ahead.lock);
    int state = ahead.state;
    pthread_mutex_unlock(&ahead.lock);
    return state == 0 ? -1 : state > 0;
}
