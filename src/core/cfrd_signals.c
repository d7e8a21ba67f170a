/* Termination signals (SIGTERM, what Slurm sends at a job's time limit, and SIGINT) are
   noted, not acted on: the program checks the note after each completed stage and closes
   its results as DECK.incomplete.h5 (src/core/cfrd_signals.f90, app/main.f90). */
#include <signal.h>
#include <string.h>

static volatile sig_atomic_t received = 0;

static void note_signal(int number) { received = number; }

void cfrd_catch_termination(void)
{
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = note_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGTERM, &action, 0);
    sigaction(SIGINT, &action, 0);
}

int cfrd_termination_signal(void) { return (int) received; }
