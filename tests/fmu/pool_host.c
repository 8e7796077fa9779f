/* A master with a thread pool, in C: instances of an FMI 2.0 co-simulation FMU, one per value of a
   real parameter, each driven at casing.A.z by 2e-5 sin(2 pi 300 t) m, stepped one after the other
   (serially) and at once (a thread each), `reps` times, the two in alternate order. The instances are made
   and initialised before the clock starts and freed after it stops: only the steps are timed.
   Prints "time serial S threads T" (s) per repetition, then every instance's output per step of
   the first serial run as "y I VALUE"; exits 3 if a threaded run's outputs differ from the serial
   run's in any bit.
   usage: pool_host so guid resources_uri n h reps vr_u vr_v vr_a vr_out vr_param value0 [value1 ...] */
#include <dlfcn.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment e, fmi2String n, fmi2Status s, fmi2String c, fmi2String m, ...) {
    (void)e, (void)n, (void)c;
    if (s > fmi2Warning) printf("log %d: %s\n", s, m);
}
static fmi2InstantiateTYPE *instantiate;
static fmi2SetupExperimentTYPE *setup;
static fmi2EnterInitializationModeTYPE *enter;
static fmi2ExitInitializationModeTYPE *exit_init;
static fmi2SetRealTYPE *set_real;
static fmi2GetRealTYPE *get_real;
static fmi2DoStepTYPE *do_step;
static fmi2TerminateTYPE *terminate;
static fmi2FreeInstanceTYPE *free_instance;
static const char *guid, *uri;
static int n;
static double h;
static fmi2ValueReference in[3], out, param;

typedef struct {
    double value;
    fmi2Component c;
    double *y;
    int status;
} Job;

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int make(Job *job) {
    static const fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    job->c = instantiate("pool", fmi2CoSimulation, guid, uri, &cb, fmi2False, fmi2False);
    if (!job->c) return 100;
    if (set_real(job->c, &param, 1, &job->value) || setup(job->c, fmi2False, 0.0, 0.0, fmi2False, 0.0)
        || enter(job->c) || exit_init(job->c))
        return 101;
    return 0;
}

static void *steps(void *arg) {
    Job *job = arg;
    double w = 2.0 * M_PI * 300.0, a = 2e-5;
    for (int k = 0; k < n && !job->status; k++) {
        double t = k * h, u[3] = {a * sin(w * t), a * w * cos(w * t), -a * w * w * sin(w * t)};
        if (set_real(job->c, in, 3, u) || do_step(job->c, t, h, fmi2True) || get_real(job->c, &out, 1, job->y + k))
            job->status = 200;
    }
    return NULL;
}

static void finish(Job *job) {
    terminate(job->c);
    free_instance(job->c);
}

int main(int argc, char **argv) {
    if (argc < 13) return 1;
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        printf("dlopen failed: %s\n", dlerror());
        return 1;
    }
#define LOAD(v, f) v = (f##TYPE *)dlsym(lib, #f)
    LOAD(instantiate, fmi2Instantiate);
    LOAD(setup, fmi2SetupExperiment);
    LOAD(enter, fmi2EnterInitializationMode);
    LOAD(exit_init, fmi2ExitInitializationMode);
    LOAD(set_real, fmi2SetReal);
    LOAD(get_real, fmi2GetReal);
    LOAD(do_step, fmi2DoStep);
    LOAD(terminate, fmi2Terminate);
    LOAD(free_instance, fmi2FreeInstance);
    guid = argv[2], uri = argv[3], n = atoi(argv[4]), h = atof(argv[5]);
    int reps = atoi(argv[6]), m = argc - 12;
    for (int i = 0; i < 3; i++) in[i] = (fmi2ValueReference)atoi(argv[7 + i]);
    out = (fmi2ValueReference)atoi(argv[10]), param = (fmi2ValueReference)atoi(argv[11]);
    Job *ser = calloc(m, sizeof(Job)), *par = calloc(m, sizeof(Job));
    pthread_t *th = calloc(m, sizeof(pthread_t));
    for (int i = 0; i < m; i++) {
        ser[i].value = par[i].value = atof(argv[12 + i]);
        ser[i].y = calloc(n, sizeof(double)), par[i].y = calloc(n, sizeof(double));
    }
    for (int r = 0; r < reps; r++) {
        for (int i = 0; i < m; i++)
            if ((ser[i].status = make(ser + i)) || (par[i].status = make(par + i))) {
                printf("instance %d did not initialise\n", i);
                return 2;
            }
        double serial = 0.0, threads = 0.0;
        for (int phase = 0; phase < 2; phase++) {   /* the two orders alternate with the repetitions */
            double t0 = now();
            if ((phase + r) % 2 == 0) {
                for (int i = 0; i < m; i++) steps(ser + i);
                serial = now() - t0;
            } else {
                for (int i = 0; i < m; i++) pthread_create(th + i, NULL, steps, par + i);
                for (int i = 0; i < m; i++) pthread_join(th[i], NULL);
                threads = now() - t0;
            }
        }
        for (int i = 0; i < m; i++) finish(ser + i), finish(par + i);
        printf("time serial %.6f threads %.6f\n", serial, threads);
        for (int i = 0; i < m; i++) {
            if (ser[i].status || par[i].status) {
                printf("instance %d: a step failed (serial %d, threads %d)\n", i, ser[i].status, par[i].status);
                return 2;
            }
            if (memcmp(ser[i].y, par[i].y, n * sizeof(double))) {
                printf("instance %d: the threaded run differs from the serial run\n", i);
                return 3;
            }
        }
    }
    for (int i = 0; i < m; i++)
        for (int k = 0; k < n; k++) printf("y %d %.17g\n", i, ser[i].y[k]);
    dlclose(lib);
    return 0;
}
