/* A plain C host of CableCasing.fmu (no Python of its own) for what only such a host shows:
   usage: plain_c_host so guid resources_uri MODE
   signal default|handler  SIGINT left at SIG_DFL or given a handler of the host's before loading; prints its
                           disposition before and after fmi2Instantiate ("sigint before D after D"), then a
                           thread sends SIGINT 0.3 s after "step starts" is printed, into a doStep of 1 s
                           (~2 s of work): with SIG_DFL the process dies of it (as with any C FMU) before
                           "doStep returned"; with the host's handler "doStep S handler N" is printed
   python                  SIGINT at SIG_DFL: after fmi2Instantiate (which started Python), runs in Python's
                           main thread what Python code does with SIGINT: the save/restore idiom
                           (old = signal.signal(SIGINT, h); signal.signal(SIGINT, old)) and asyncio.run; prints
                           Python's record ("python: getsignal G") and the kernel's disposition after
                           ("python: rc R sigint D")
   steps                   logging on: 2 steps of 1e-12 s (a clock's rounding), 3 of 1e-4 s, fmi2Terminate;
                           prints the log
   reload                  instantiate (logging on), free, dlclose, dlopen, instantiate again: prints the log
   nulllogger on|off       callbacks without a logger (FMI 2.0 does not allow it), logging on or off:
                           instantiate, step, terminate, free */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "fmi2Functions.h"

static const char *so, *guid, *uri;
static void *lib;
static fmi2InstantiateTYPE *instantiate;
static fmi2SetupExperimentTYPE *setup;
static fmi2EnterInitializationModeTYPE *enter;
static fmi2ExitInitializationModeTYPE *exit_init;
static fmi2DoStepTYPE *do_step;
static fmi2TerminateTYPE *terminate;
static fmi2FreeInstanceTYPE *free_instance;

static void logger(fmi2ComponentEnvironment e, fmi2String n, fmi2Status s, fmi2String c, fmi2String m, ...) {
    (void)e, (void)n, (void)c;
    printf("log %d: %s\n", s, m);
    fflush(stdout);
}

static void load(void) {
    lib = dlopen(so, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        printf("dlopen: %s\n", dlerror());
        exit(2);
    }
    instantiate = (fmi2InstantiateTYPE *)dlsym(lib, "fmi2Instantiate");
    setup = (fmi2SetupExperimentTYPE *)dlsym(lib, "fmi2SetupExperiment");
    enter = (fmi2EnterInitializationModeTYPE *)dlsym(lib, "fmi2EnterInitializationMode");
    exit_init = (fmi2ExitInitializationModeTYPE *)dlsym(lib, "fmi2ExitInitializationMode");
    do_step = (fmi2DoStepTYPE *)dlsym(lib, "fmi2DoStep");
    terminate = (fmi2TerminateTYPE *)dlsym(lib, "fmi2Terminate");
    free_instance = (fmi2FreeInstanceTYPE *)dlsym(lib, "fmi2FreeInstance");
}

static fmi2Component make(const fmi2CallbackFunctions *cb, int logging) {
    fmi2Component c = instantiate("plain", fmi2CoSimulation, guid, uri, cb, fmi2False, logging ? fmi2True : fmi2False);
    if (!c) {
        printf("instantiate failed\n");
        exit(3);
    }
    if (setup(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) || enter(c) || exit_init(c)) {
        printf("initialisation failed\n");
        exit(4);
    }
    return c;
}

static volatile sig_atomic_t got = 0;
static void handler(int sig) { got = sig; }
static void *killer(void *p) {
    (void)p;
    usleep(300000);
    kill(getpid(), SIGINT);
    return NULL;
}
static const char *disposition(void) {
    struct sigaction sa;
    sigaction(SIGINT, NULL, &sa);
    return sa.sa_handler == SIG_DFL ? "default" : sa.sa_handler == handler ? "host" : "other";
}

int main(int argc, char **argv) {
    static const fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    if (argc < 5) return 2;
    setvbuf(stdout, NULL, _IOLBF, 0);
    so = argv[1], guid = argv[2], uri = argv[3];
    const char *mode = argv[4], *arg = argc > 5 ? argv[5] : "";
    if (!strcmp(mode, "signal") && !strcmp(arg, "handler")) {
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = handler;
        sigaction(SIGINT, &sa, NULL);
    }
    load();
    if (!strcmp(mode, "signal")) {
        const char *before = disposition();
        fmi2Component c = make(&cb, 0);
        printf("sigint before %s after %s\n", before, disposition());
        printf("step starts\n");
        pthread_t th;
        pthread_create(&th, NULL, killer, NULL);
        fmi2Status s = do_step(c, 0.0, 1.0, fmi2True);
        printf("doStep returned\n");
        pthread_join(th, NULL);
        printf("doStep %d handler %d\n", s, (int)got);
        free_instance(c);
    } else if (!strcmp(mode, "python")) {
        fmi2Component c = make(&cb, 0);
        /* libpython is loaded with global symbols by the FMU, which started Python in this thread */
        int (*ensure)(void) = (int (*)(void))dlsym(RTLD_DEFAULT, "PyGILState_Ensure");
        void (*release)(int) = (void (*)(int))dlsym(RTLD_DEFAULT, "PyGILState_Release");
        int (*run)(const char *) = (int (*)(const char *))dlsym(RTLD_DEFAULT, "PyRun_SimpleString");
        if (!ensure || !release || !run) {
            printf("no Python symbols\n");
            return 5;
        }
        int g = ensure();
        int rc = run("import asyncio, signal\n"
                     "old = signal.signal(signal.SIGINT, lambda s, f: None)\n"
                     "signal.signal(signal.SIGINT, old)\n"
                     "async def nothing():\n"
                     "    pass\n"
                     "asyncio.run(nothing())\n"
                     "print('python: getsignal', repr(signal.getsignal(signal.SIGINT)), flush=True)\n");
        release(g);
        printf("python: rc %d sigint %s\n", rc, disposition());
        free_instance(c);
    } else if (!strcmp(mode, "steps")) {
        fmi2Component c = make(&cb, 1);
        double t = 0.0;
        for (int k = 0; k < 5; k++) {
            double h = (k == 1 || k == 3) ? 1e-12 : 1e-4;
            printf("step %g -> %d\n", h, do_step(c, t, h, fmi2True));
            t += h;
        }
        terminate(c);
        free_instance(c);
    } else if (!strcmp(mode, "reload")) {
        for (int k = 0; k < 2; k++) {
            if (k) load();
            printf("load %d\n", k);
            fmi2Component c = make(&cb, 1);
            free_instance(c);
            dlclose(lib);
        }
        return 0;
    } else if (!strcmp(mode, "nulllogger")) {
        static const fmi2CallbackFunctions none = {NULL, calloc, free, NULL, NULL};
        fmi2Component c = make(&none, !strcmp(arg, "on"));
        printf("step -> %d\n", do_step(c, 0.0, 1e-4, fmi2True));
        terminate(c);
        free_instance(c);
    }
    dlclose(lib);
    return 0;
}
