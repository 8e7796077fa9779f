/* A C host of CableCasing.fmu for fmi2SetDebugLogging's categories, NULL output arguments and the status
   functions before initialisation (review BB4-BB6; tests/fmu/test_review_bb_fmu.py):
   usage: status_args_host so guid resources_uri MODE vr_z vr_out vr_int vr_bool vr_str
   (vr_z: the input casing.A.z; vr_out a Real output, vr_int an Integer output, vr_bool a Boolean and vr_str
   a String parameter)
   logging   instances set up as each line says (loggingOn at fmi2Instantiate, then fmi2SetDebugLogging
             calls, each printed with its status: "set S"), then one run that logs one warning (casing.A.z
             not 0 at the start), one discard (a step of 1e-9 s), one error (a step of 0 s) and, with
             logging on, informational lines (the tolerance, the timing report); prints
             "run NAME info I warning W discard D error E", the messages counted by status during the run
   nullargs  in each state (instantiated, initialization, stepping, terminated) every exported function
             that takes an output pointer or array, with NULL there: "null STATE CALL -> S lines N: LAST"
             (its status, the logger lines it gave, the last); then a step: "after STATE step -> S"
   status    the status functions in Instantiated (before and after fmi2SetupExperiment with startTime
             0.25 s) and in Initialization Mode: "status STATE KIND -> S value V" */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"

static const char *guid, *uri;
static fmi2ValueReference vr_z, vr_out, vr_int, vr_bool, vr_str;
static int counts[6], lines;
static char last[4096];

#define FN(name) static fmi2##name##TYPE *name;
#define FNS(X)                                                                                         \
    X(Instantiate) X(FreeInstance) X(SetDebugLogging) X(SetupExperiment) X(EnterInitializationMode)     \
    X(ExitInitializationMode) X(Terminate) X(DoStep) X(GetReal) X(GetInteger) X(GetBoolean) X(GetString) \
    X(SetReal) X(SetInteger) X(SetBoolean) X(SetString) X(GetStatus) X(GetRealStatus) X(GetIntegerStatus) \
    X(GetBooleanStatus) X(GetStringStatus) X(GetFMUstate) X(FreeFMUstate) X(SerializedFMUstateSize)     \
    X(SerializeFMUstate) X(DeSerializeFMUstate) X(SetFMUstate)
FNS(FN)

static void logger(fmi2ComponentEnvironment e, fmi2String n, fmi2Status s, fmi2String c, fmi2String m, ...) {
    (void)e, (void)n, (void)c;
    if (s <= fmi2Pending) counts[s]++;
    lines++;
    snprintf(last, sizeof last, "%s", m ? m : "");
}
static const fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};

static void reset_counts(void) {
    memset(counts, 0, sizeof counts);
    lines = 0;
    last[0] = 0;
}

static fmi2Component make(const char *name, int logging) {
    fmi2Component c = Instantiate(name, fmi2CoSimulation, guid, uri, &cb, fmi2False, logging ? fmi2True : fmi2False);
    if (!c) {
        printf("instantiate failed\n");
        exit(3);
    }
    return c;
}

/* one warning, one discard, one error, and informational lines with logging on */
static void one_run(const char *name, fmi2Component c) {
    reset_counts();
    fmi2Real z = 1e-5;
    SetupExperiment(c, fmi2True, 1e-6, 0.0, fmi2False, 0.0);
    EnterInitializationMode(c);
    ExitInitializationMode(c);
    SetReal(c, &vr_z, 1, &z);
    DoStep(c, 0.0, 1e-4, fmi2True);
    DoStep(c, 1e-4, 1e-9, fmi2True);
    DoStep(c, 1e-4, 0.0, fmi2True);
    Terminate(c);
    printf("run %s info %d warning %d discard %d error %d\n", name, counts[fmi2OK], counts[fmi2Warning],
           counts[fmi2Discard], counts[fmi2Error]);
}

static void set(fmi2Component c, int on, size_t n, const char *a, const char *b) {
    fmi2String cats[2] = {a, b};
    printf("set %d\n", SetDebugLogging(c, on ? fmi2True : fmi2False, n, n ? cats : NULL));
}

static void logging(void) {
    fmi2Component c = make("off", 0);
    one_run("off", c);
    FreeInstance(c);
    c = make("on", 1);
    one_run("on", c);
    FreeInstance(c);
    c = make("discard_off", 1);
    set(c, 0, 1, "logStatusDiscard", NULL);
    one_run("discard_off", c);
    FreeInstance(c);
    c = make("warning_off", 0);
    set(c, 0, 1, "logStatusWarning", NULL);
    one_run("warning_off", c);
    FreeInstance(c);
    c = make("both_off_discard_on", 0);
    set(c, 0, 2, "logStatusWarning", "logStatusDiscard");
    set(c, 1, 1, "logStatusDiscard", NULL);
    one_run("both_off_discard_on", c);
    FreeInstance(c);
    c = make("errors_off", 0);
    set(c, 0, 2, "logStatusError", "logStatusFatal");
    one_run("errors_off", c);
    FreeInstance(c);
    c = make("none_off", 1);
    set(c, 0, 0, NULL, NULL);
    one_run("none_off", c);
    FreeInstance(c);
    c = make("none_on", 0);
    set(c, 0, 2, "logStatusWarning", "logStatusDiscard");
    set(c, 1, 0, NULL, NULL);
    one_run("none_on", c);
    FreeInstance(c);
    c = make("logall_off", 1);
    set(c, 0, 1, "logAll", NULL);
    one_run("logall_off", c);
    FreeInstance(c);
    c = make("bad_category", 0);
    set(c, 0, 2, "logStatusDiscard", "noSuchCategory");
    one_run("bad_category", c);
    FreeInstance(c);
    /* per instance: both live, the first one's discards off */
    fmi2Component a = make("quiet", 0), b = make("loud", 0);
    set(a, 0, 1, "logStatusDiscard", NULL);
    one_run("quiet", a);
    one_run("loud", b);
    FreeInstance(a);
    FreeInstance(b);
}

#define NULLCALL(call)                                                                                 \
    do {                                                                                               \
        reset_counts();                                                                                \
        fmi2Status s_ = call;                                                                          \
        printf("null %s %s -> %d lines %d: %s\n", state, #call, s_, lines, last);                      \
    } while (0)

static void null_calls(fmi2Component c, const char *state) {
    fmi2Real r = 0.0;
    fmi2Integer i = 0;
    fmi2Boolean b = 0;
    fmi2String str = "";
    fmi2FMUstate st = NULL, st2 = NULL;
    size_t size = 0;
    GetFMUstate(c, &st);
    SerializedFMUstateSize(c, st, &size);
    fmi2Byte *bytes = malloc(size ? size : 1);
    SerializeFMUstate(c, st, bytes, size);
    NULLCALL(GetReal(c, &vr_out, 1, NULL));
    NULLCALL(GetReal(c, NULL, 1, &r));
    NULLCALL(GetInteger(c, &vr_int, 1, NULL));
    NULLCALL(GetBoolean(c, &vr_bool, 1, NULL));
    NULLCALL(GetString(c, &vr_str, 1, NULL));
    NULLCALL(SetReal(c, &vr_z, 1, NULL));
    NULLCALL(SetInteger(c, NULL, 1, &i));
    NULLCALL(SetBoolean(c, &vr_bool, 1, NULL));
    NULLCALL(SetString(c, &vr_str, 1, NULL));
    NULLCALL(GetStatus(c, fmi2DoStepStatus, NULL));
    NULLCALL(GetRealStatus(c, fmi2LastSuccessfulTime, NULL));
    NULLCALL(GetIntegerStatus(c, fmi2LastSuccessfulTime, NULL));
    NULLCALL(GetBooleanStatus(c, fmi2Terminated, NULL));
    NULLCALL(GetStringStatus(c, fmi2PendingStatus, NULL));
    NULLCALL(GetFMUstate(c, NULL));
    NULLCALL(SerializedFMUstateSize(c, st, NULL));
    NULLCALL(SerializeFMUstate(c, st, NULL, size));
    NULLCALL(DeSerializeFMUstate(c, NULL, size, &st2));
    NULLCALL(DeSerializeFMUstate(c, bytes, size, NULL));
    NULLCALL(SetFMUstate(c, NULL));
    NULLCALL(SerializedFMUstateSize(c, NULL, &size));
    NULLCALL(SerializeFMUstate(c, NULL, bytes, size));
    (void)b, (void)str;
    free(bytes);
    FreeFMUstate(c, &st);
}

static void nullargs(void) {
    fmi2Component c = make("nullargs", 0);
    null_calls(c, "instantiated");
    SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    EnterInitializationMode(c);
    null_calls(c, "initialization");
    ExitInitializationMode(c);
    null_calls(c, "stepping");
    printf("after stepping step -> %d\n", DoStep(c, 0.0, 1e-4, fmi2True));
    Terminate(c);
    null_calls(c, "terminated");
    fmi2Real r = -1.0;
    printf("after terminated get -> %d\n", GetReal(c, &vr_out, 1, &r));
    FreeInstance(c);
}

static void statuses(fmi2Component c, const char *state) {
    fmi2Status s = fmi2Fatal;
    fmi2Real r = -1.0;
    fmi2Boolean b = 7;
    fmi2Status got = GetStatus(c, fmi2DoStepStatus, &s);   /* (called before the value is printed) */
    printf("status %s doStep -> %d value %d\n", state, got, (int)s);
    got = GetRealStatus(c, fmi2LastSuccessfulTime, &r);
    printf("status %s lastSuccessfulTime -> %d value %.17g\n", state, got, r);
    got = GetBooleanStatus(c, fmi2Terminated, &b);
    printf("status %s terminated -> %d value %d\n", state, got, (int)b);
}

static void status(void) {
    fmi2Component c = make("status", 0);
    statuses(c, "instantiated");
    SetupExperiment(c, fmi2False, 0.0, 0.25, fmi2False, 0.0);
    statuses(c, "setup");
    EnterInitializationMode(c);
    statuses(c, "initialization");
    ExitInitializationMode(c);
    printf("step -> %d\n", DoStep(c, 0.25, 1e-4, fmi2True));
    statuses(c, "stepping");
    FreeInstance(c);
}

#define RESOLVE(name)                                                                                  \
    if (!(name = (fmi2##name##TYPE *)dlsym(lib, "fmi2" #name))) {                                       \
        printf("no fmi2" #name "\n");                                                                  \
        return 2;                                                                                      \
    }

int main(int argc, char **argv) {
    if (argc < 10) return 2;
    setvbuf(stdout, NULL, _IOLBF, 0);
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        printf("dlopen: %s\n", dlerror());
        return 2;
    }
    FNS(RESOLVE)
    guid = argv[2], uri = argv[3];
    vr_z = (fmi2ValueReference)atol(argv[5]), vr_out = (fmi2ValueReference)atol(argv[6]);
    vr_int = (fmi2ValueReference)atol(argv[7]), vr_bool = (fmi2ValueReference)atol(argv[8]);
    vr_str = (fmi2ValueReference)atol(argv[9]);
    if (!strcmp(argv[4], "logging")) logging();
    else if (!strcmp(argv[4], "nullargs")) nullargs();
    else if (!strcmp(argv[4], "status")) status();
    printf("end\n");
    return 0;
}
