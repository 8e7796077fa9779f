/* FMI 2.0 co-simulation entry points of CableCasing.fmu (Linux), the binary in binaries/linux64/.
 *
 * The model is Python (resources/: the bridge, the slave and the cablecasing_core package); this
 * file only hosts it. What it does that pythonfmu's binary does not (docs/fmu.md, "Use in a
 * system simulator"):
 *
 *  - It finds CPython itself. The binary does not link libpython: in a Python host it uses the
 *    host's interpreter (its symbols are already in the process); in any other host it reads the
 *    interpreter recorded at build time (resources/python-environment.txt), or the one named by
 *    CABLECASING_PYTHON, loads its libpython with RTLD_GLOBAL and starts it with an isolated
 *    configuration (PYTHONHOME/PYTHONPATH of the host's environment are ignored) in UTF-8 mode
 *    (paths with non-ASCII characters work under the "C" locale), so a plain environment is enough. Every Python function is called through a pointer from dlsym, so no
 *    Python symbol is left for the dynamic loader to resolve. SIGINT stays the host's (start_python).
 *  - It never finalises the interpreter. Py_Finalize with numpy/scipy/numba loaded crashes at
 *    exit (the C host's SIGSEGV of pythonfmu's worker thread); the process's own exit reclaims
 *    everything. No thread, atexit handler or static destructor of this library outlives
 *    fmi2FreeInstance, so a host may unload the binary at any time.
 *  - A host thread gets one Python thread state for good on its first call (PyGILState_Ensure
 *    otherwise creates and destroys one per call, ~7 us), the first MAX_KEPT_THREAD_STATES threads
 *    only: a host that calls from a new thread each time (std::async, a thread per task) would
 *    otherwise leave one (~4.4 kB) per call; its later threads pay the ~7 us instead.
 *  - A component pointer is looked up among the live instances before it is read, so that a
 *    pointer that is not one (freed, another FMU's, garbage) is fmi2Error, not a crash.
 *  - Support inputs and outputs live in two arrays that the Python instance allocated and fills:
 *    fmi2SetReal of inputs and fmi2GetReal/fmi2GetInteger of outputs never enter Python (outside
 *    Initialization Mode, where the outputs are computed from the parameters set so far).
 *  - Every other call returns the status the Python side decided (fmi2Error and fmi2Discard
 *    with a message for the host's logger); an exception that escapes anyway becomes fmi2Error.
 *    Nothing here returns fmi2Fatal.
 *
 * Built by build_fmu.py against the build interpreter's Python.h (for the PyConfig layout only;
 * the runtime interpreter must have the same major.minor version when this file starts it).
 */
#define _GNU_SOURCE
#include <Python.h>

#include <ctype.h>
#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "fmi2Functions.h"

#ifndef CC_PY_MAJOR
#define CC_PY_MAJOR PY_MAJOR_VERSION
#define CC_PY_MINOR PY_MINOR_VERSION
#endif

/* ------------------------------------------------------------------------------------------------
 * The Python C API, through pointers (the prototypes come from Python.h; typeof takes no address)
 */
#define PYAPI(X)                                                                                       \
    X(Py_IsInitialized) X(Py_GetVersion) X(PyConfig_InitIsolatedConfig) X(PyConfig_SetBytesString)     \
    X(PyConfig_Clear) X(Py_InitializeFromConfig) X(PyEval_SaveThread) X(PyGILState_Ensure)            \
    X(PyGILState_Release) X(PyGILState_GetThisThreadState) X(PyRun_StringFlags) X(PyDict_New)              \
    X(PyDict_SetItemString) X(PyDict_GetItemString) X(PyEval_GetBuiltins) X(PyObject_GetAttrString)   \
    X(PyObject_CallObject) X(PyObject_Str) X(PyTuple_New) X(PyTuple_SetItem) X(PyLong_FromVoidPtr)    \
    X(PyLong_FromSize_t) X(PyLong_FromLong) X(PyLong_AsLong) X(PyLong_AsSsize_t) X(PyLong_AsVoidPtr)  \
    X(PyFloat_FromDouble) X(PyFloat_AsDouble) X(PyUnicode_FromString) X(PyUnicode_AsUTF8)             \
    X(PyBytes_FromStringAndSize) X(PyErr_Occurred) X(PyErr_Fetch) X(PyErr_NormalizeException)         \
    X(PyErr_Clear) X(Py_DecRef) X(Py_IncRef) X(PyBool_FromLong) X(PyBytes_Size) X(PyBytes_AsString)     \
    X(PyObject_IsTrue) X(PyStatus_Exception) X(PyPreConfig_InitIsolatedConfig) X(Py_PreInitialize)     \
    X(PyImport_ImportModule) X(PySys_SetObject)

#define PYAPI_MEMBER(name) __typeof__(&name) name;
static struct { PYAPI(PYAPI_MEMBER) } P;
#define PYAPI_NAME(name) #name,
static const char *PYAPI_NAMES[] = {PYAPI(PYAPI_NAME) NULL};

static pthread_mutex_t g_python_lock = PTHREAD_MUTEX_INITIALIZER;
static int g_python_ready = 0;          /* P filled and the interpreter running */
static char g_python_note[2048] = "";   /* which interpreter, and how it was found (for the log) */

/* ------------------------------------------------------------------------------------------------
 * The instance
 */
enum { S_INSTANTIATED, S_INITIALIZATION, S_STEPPING, S_TERMINATED };
#define MAX_INT_OUTPUTS 8

/* A link of a list of live objects (live_find), the first member of each, so that its address is
 * the object's. The host holds a handle, not the address: a number unique in the process and never
 * given twice, so that a handle the host kept after freeing its object is refused even when the
 * allocator has given the same memory to a new object (a stale instance pointer acted on the new
 * instance with fmi2OK). A handle from the host is looked up among the objects this FMU made and has
 * not freed before anything is read, and one that is none of them (freed, another FMU's, garbage,
 * or a host that passes a state where fmi2FreeFMUstate takes its address, as fmusim 0.0.39 does when
 * it saves or restores a state file) is told apart without reading the memory it points at. The
 * handles have the address space's top bit set (the kernel's half on x86-64 and AArch64), so a host
 * that reads through one stops at once instead of reading another object, and a value with that bit
 * is never read as a pointer here either. Their bits 44-58 are a salt of this copy of the binary
 * (its load address and the time of its first handle; 2^-15 odds that two copies draw the same):
 * two FMUs, or two unpacked copies of one, loaded in one process do not give the same handles, so
 * each refuses the other's. */
typedef struct Live {
    struct Live *next;
    void *handle;                       /* what the host holds */
} Live;

static pthread_mutex_t live_lock = PTHREAD_MUTEX_INITIALIZER;
static uintptr_t g_handles = 0;         /* handles given so far (under live_lock) */
static uintptr_t g_salt = 0;            /* this copy's salt (under live_lock) */
static int g_salted = 0;                /* made (at the first handle) */
#define HANDLE_BASE ((uintptr_t)1 << (8 * sizeof(void *) - 1))

/* A value with the top bit set: one of the FMU's handles, never a host's pointer to read through */
static int is_handle(const void *p) { return ((uintptr_t)p & HANDLE_BASE) != 0; }

static uintptr_t handle_salt(void) {
    if (sizeof(void *) < 8) return 0;   /* (32-bit: no room; only linux64 is built) */
    uint64_t copy = ((uint64_t)(uintptr_t)&g_handles >> 12) ^ (uint64_t)time(NULL);
    return (uintptr_t)((copy & 0x7FFF) << 44);
}

/* The object of ``list`` whose handle is ``p``, or NULL */
static Live *live_find(Live *const *list, const void *p) {
    Live *found = NULL;
    pthread_mutex_lock(&live_lock);
    for (Live *l = *list; l && !found; l = l->next)
        if (l->handle == p) found = l;
    pthread_mutex_unlock(&live_lock);
    return found;
}

/* Add ``l`` to ``list`` with a new handle, and return the handle */
static void *live_add(Live **list, Live *l) {
    pthread_mutex_lock(&live_lock);
    if (!g_salted) g_salt = handle_salt(), g_salted = 1;
    l->handle = (void *)(HANDLE_BASE | g_salt | (++g_handles << 4));
    l->next = *list;
    *list = l;
    pthread_mutex_unlock(&live_lock);
    return l->handle;
}

static void live_remove(Live **list, const Live *l) {
    pthread_mutex_lock(&live_lock);
    for (Live **q = list; *q; q = &(*q)->next) {
        if (*q == l) {
            *q = l->next;
            break;
        }
    }
    pthread_mutex_unlock(&live_lock);
}

typedef struct {
    Live live;                          /* first: the list of live instances (live_instances) */
    unsigned magic;
    fmi2CallbackFunctions cb;
    char name[256];
    unsigned log_shown;                 /* the statuses whose messages reach the logger (log_shown) */
    int state;
    PyObject *py;                       /* the bridge's Instance */
    PyObject *m_do_step;                /* its bound do_step, called every step */
    PyObject *slave;                    /* the object do_step is bound to (its clock_only_calls) */
    long clock_only_seen;               /* the slave's clock_only_calls after the last counted call */
    double *inputs;                     /* owned by py: support inputs (fast path) */
    double *outputs;                    /* owned by py: outputs after the last step */
    fmi2ValueReference in0, nin, out0, nout;
    fmi2ValueReference int_vr[MAX_INT_OUTPUTS];
    size_t int_idx[MAX_INT_OUTPUTS];
    size_t nint;
    long step_calls;                    /* fmi2DoStep calls that took their step (status OK or Warning)
                                           since instantiation or reset; refused calls and those that only
                                           moved the clock (a step within its rounding) are not counted */
    double step_seconds;                /* wall time spent inside them (s) */
    double first_step_at;               /* monotonic clock at the first of them (s) */
    double longest_step;                /* wall time of the longest of them (s) */
    double longest_step_at;             /* its currentCommunicationPoint (s) */
    long late_calls;                    /* calls that took longer than their communicationStepSize */
} Instance;

static double monotonic_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#define INSTANCE_MAGIC 0xCAB1EC45u
#define STATE_MAGIC 0x57A7E0CCu

typedef struct State {
    Live live;                          /* first: the list of live states (live_states) */
    unsigned magic;
    Instance *owner;                    /* the instance whose fmi2GetFMUstate or fmi2DeSerializeFMUstate made
                                           it (or last filled it in place): fmi2FreeInstance frees it */
    PyObject *state;                    /* the bridge's state object */
    PyObject *bytes;                    /* its serialisation, while the host asks for size then data */
} State;

/* Every state and every instance this FMU made and has not freed (see Live). */
static Live *live_states = NULL;
static Live *live_instances = NULL;

/* ------------------------------------------------------------------------------------------------
 * Logging: to the host's logger and, for problems that keep the FMU from starting, also to stderr.
 * Which messages reach the logger is an instance's set of statuses (log_shown), switched per category
 * by fmi2SetDebugLogging: informational ones (logAll) when logging is on, warnings (logStatusWarning)
 * and discards (logStatusDiscard) unless switched off, errors and fatal messages always.
 */
#define SHOW_INFO (1u << fmi2OK)
#define SHOW_WARNING (1u << fmi2Warning)
#define SHOW_DISCARD (1u << fmi2Discard)
#define SHOW_ALL (SHOW_INFO | SHOW_WARNING | SHOW_DISCARD)

/* Whether a message of ``status`` reaches the logger when ``shown`` is the set of statuses shown */
static int log_shown(unsigned shown, fmi2Status status) {
    return status >= fmi2Error || (shown & (1u << status)) != 0;
}

static void escape_for_logger(const char *msg, char *out, size_t size) {
    /* the logger's message is a printf format in which '#' starts a value reference: '%%', '##' */
    size_t j = 0;
    for (size_t i = 0; msg[i] && j + 3 < size; i++) {
        if (msg[i] == '%' || msg[i] == '#') out[j++] = msg[i];
        out[j++] = msg[i];
    }
    out[j] = 0;
}

static void log_to_host(const fmi2CallbackFunctions *cb, const char *name, unsigned shown, fmi2Status status,
                        const char *category, const char *msg, int also_stderr) {
    if (also_stderr || ((!cb || !cb->logger) && log_shown(shown, status))) {
        /* (no logger, which FMI 2.0 does not allow: what the host would have been told goes to stderr) */
        static const char *labels[] = {"OK", "WARNING", "DISCARD", "ERROR", "FATAL", "PENDING"};
        fprintf(stderr, "[CableCasing %s] %s\n", labels[status <= 5 ? status : 3], msg);
        fflush(stderr);
    }
    if (cb && cb->logger && log_shown(shown, status)) {
        size_t size = 2 * strlen(msg) + 4;
        char *buf = malloc(size);
        if (!buf) return;
        escape_for_logger(msg, buf, size);
        cb->logger(cb->componentEnvironment, name ? name : "", status, category, buf);
        free(buf);
    }
}

static void logf_to_host(const fmi2CallbackFunctions *cb, const char *name, unsigned shown, fmi2Status status,
                         int also_stderr, const char *fmt, ...) {
    char msg[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    /* the categories of the modelDescription, as the Python side's messages take them */
    const char *category = status >= fmi2Error     ? "logStatusError"
                           : status == fmi2Discard ? "logStatusDiscard"
                           : status == fmi2Warning ? "logStatusWarning"
                                                   : "logAll";
    log_to_host(cb, name, shown, status, category, msg, also_stderr);
}

#define LOGI(inst, status, ...) logf_to_host(&(inst)->cb, (inst)->name, (inst)->log_shown, status, 0, __VA_ARGS__)

/* called by the Python side (through ctypes, without the GIL) for every message */
static void bridge_log(void *handle, int status, const char *category, const char *message, int also_stderr) {
    Instance *inst = handle;
    log_to_host(&inst->cb, inst->name, inst->log_shown, (fmi2Status)status, category ? category : "logAll",
                message ? message : "", also_stderr);
}

/* ------------------------------------------------------------------------------------------------
 * Finding and starting Python
 */
static int resolve_api(void *handle, char *err, size_t errsize) {
    void **slot = (void **)&P;
    for (int i = 0; PYAPI_NAMES[i]; i++) {
        slot[i] = dlsym(handle, PYAPI_NAMES[i]);
        if (!slot[i]) {
            snprintf(err, errsize, "the Python library lacks the function %s (is it CPython %d.%d?)",
                     PYAPI_NAMES[i], CC_PY_MAJOR, CC_PY_MINOR);
            return 0;
        }
    }
    return 1;
}

static void trim(char *s) {
    size_t n = strlen(s);
    while (n && isspace((unsigned char)s[n - 1])) s[--n] = 0;
}

/* key=value of resources/python-environment.txt; empty when absent */
static void environment_value(const char *resources, const char *key, char *out, size_t size) {
    char path[PATH_MAX], line[PATH_MAX + 64];
    out[0] = 0;
    snprintf(path, sizeof path, "%s/python-environment.txt", resources);
    FILE *f = fopen(path, "r");
    if (!f) return;
    size_t klen = strlen(key);
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, key, klen) == 0 && line[klen] == '=') {
            snprintf(out, size, "%s", line + klen + 1);
            trim(out);
            break;
        }
    }
    fclose(f);
}

static int is_file(const char *p) {
    struct stat st;
    return p[0] && stat(p, &st) == 0 && S_ISREG(st.st_mode);
}

/* Ask an interpreter for its version and shared library: "3.11\n/prefix/lib/libpython3.11.so.1.0" */
static int query_interpreter(const char *exe, char *version, size_t vsize, char *lib, size_t lsize) {
    char cmd[PATH_MAX + 512];
    if (strchr(exe, '\'')) return 0;
    snprintf(cmd, sizeof cmd,
             "'%s' -I -c \"import sys, sysconfig, os; v = sysconfig.get_config_var; "
             "print('%%d.%%d' %% sys.version_info[:2]); "
             "print(os.path.join(v('LIBDIR') or '', v('INSTSONAME') or v('LDLIBRARY') or ''))\" 2>/dev/null",
             exe);
    FILE *p = popen(cmd, "r");
    if (!p) return 0;
    int ok = fgets(version, (int)vsize, p) && fgets(lib, (int)lsize, p);
    pclose(p);
    if (!ok) return 0;
    trim(version);
    trim(lib);
    return version[0] != 0;
}

/* The interpreter to start: CABLECASING_PYTHON, else the one recorded at build time, else
 * python<major>.<minor> on PATH. Fills exe and lib, or err. */
static int find_interpreter(const char *resources, char *exe, char *lib, char *how, char *err, size_t errsize) {
    char want[16], version[64], recorded_exe[PATH_MAX], recorded_lib[PATH_MAX];
    snprintf(want, sizeof want, "%d.%d", CC_PY_MAJOR, CC_PY_MINOR);
    environment_value(resources, "executable", recorded_exe, sizeof recorded_exe);
    environment_value(resources, "libpython", recorded_lib, sizeof recorded_lib);
    const char *env = getenv("CABLECASING_PYTHON");
    if (env && env[0]) {
        if (!query_interpreter(env, version, sizeof version, lib, PATH_MAX)) {
            snprintf(err, errsize,
                     "CABLECASING_PYTHON=%s does not run as a Python interpreter; set it to the path of a "
                     "CPython %s executable that has numpy, scipy and numba",
                     env, want);
            return 0;
        }
        if (strcmp(version, want) != 0) {
            snprintf(err, errsize,
                     "CABLECASING_PYTHON=%s is Python %s, but this FMU was built for CPython %s; set it to a "
                     "CPython %s executable (or rebuild the FMU with that Python)",
                     env, version, want, want);
            return 0;
        }
        snprintf(exe, PATH_MAX, "%s", env);
        snprintf(how, 256, "named by CABLECASING_PYTHON");
    } else if (is_file(recorded_exe) && is_file(recorded_lib)) {
        snprintf(exe, PATH_MAX, "%s", recorded_exe);
        snprintf(lib, PATH_MAX, "%s", recorded_lib);
        snprintf(how, 256, "recorded when the FMU was built");
    } else {
        char name[32];
        snprintf(name, sizeof name, "python%s", want);
        const char *path = getenv("PATH");
        int found = 0;
        if (path) {
            char *copy = strdup(path), *save = NULL;
            for (char *dir = strtok_r(copy, ":", &save); dir && !found; dir = strtok_r(NULL, ":", &save)) {
                snprintf(exe, PATH_MAX, "%s/%s", dir, name);
                found = is_file(exe) && query_interpreter(exe, version, sizeof version, lib, PATH_MAX) &&
                        strcmp(version, want) == 0;
            }
            free(copy);
        }
        if (!found) {
            snprintf(err, errsize,
                     "no CPython %s found: the interpreter recorded when the FMU was built (%s) does not exist "
                     "here, CABLECASING_PYTHON is not set and there is no %s on PATH; install CPython %s with "
                     "numpy, scipy and numba and set CABLECASING_PYTHON=/path/to/python%s",
                     want, recorded_exe[0] ? recorded_exe : "none", name, want, want);
            return 0;
        }
        snprintf(how, 256, "found on PATH");
    }
    if (!is_file(lib)) {
        snprintf(err, errsize,
                 "the Python at %s has no shared library (%s): CPython must be built with --enable-shared to "
                 "be embedded; use another CPython %s (CABLECASING_PYTHON)",
                 exe, lib[0] ? lib : "none", want);
        return 0;
    }
    return 1;
}

/* The attribute of the sys module that says this FMU's binary started the process's Python (its value:
 * the note of how), so that a binary loaded again after dlclose (libpython stays loaded, the interpreter
 * running) does not take that interpreter for a Python host's. */
#define STARTED_MARK "_cablecasing_started_by_fmu"

/* SIGINT stays the host's. CPython installs its own SIGINT handler (which raises KeyboardInterrupt in
 * Python's main thread, and never stops a C host) where SIGINT is at SIG_DFL when its _signal module is
 * first imported, whatever config.install_signal_handlers says (numba imports it, so every start would
 * take Ctrl-C away from the host). That happens once per process: the module's initialisation runs at
 * its first import only (later imports, of signal too, find it in sys.modules), so it is imported here,
 * at once (in the thread that started Python: Python's main thread), and the host's disposition put back.
 * - SIG_DFL: put back through Python (signal.signal(SIGINT, SIG_DFL)), so that Python's own record says
 *   SIG_DFL too. Put back behind its back, Python still records its handler, and Python code that saves
 *   and restores SIGINT (old = signal.signal(SIGINT, h); ...; signal.signal(SIGINT, old)), or asyncio.run
 *   (3.11 and later), would install it again.
 * - SIG_IGN: Python records SIG_IGN and installs nothing; nothing to do.
 * - A handler of the host's: Python records None ("not set from Python") and installs nothing. It cannot
 *   represent a C handler, so the check below, with the raw sigaction, is the only way to put one back.
 * The raw sigaction then restores the host's exact flags whatever happened (Python sets SA_ONSTACK). */
static void import_signal_keep_hosts_sigint(const struct sigaction *host, int have_host) {
    PyObject *m = P.PyImport_ImportModule("_signal");
    if (m) P.Py_DecRef(m);
    else P.PyErr_Clear();
    if (have_host && !(host->sa_flags & SA_SIGINFO) && host->sa_handler == SIG_DFL) {
        PyObject *globals = P.PyDict_New();
        if (globals) {
            P.PyDict_SetItemString(globals, "__builtins__", P.PyEval_GetBuiltins());
            PyObject *r = P.PyRun_StringFlags("import signal\nsignal.signal(signal.SIGINT, signal.SIG_DFL)\n",
                                              Py_file_input, globals, globals, NULL);
            if (r) P.Py_DecRef(r);
            else P.PyErr_Clear();
            P.Py_DecRef(globals);
        } else {
            P.PyErr_Clear();
        }
    }
    struct sigaction now;
    if (have_host && sigaction(SIGINT, NULL, &now) == 0 &&
        (now.sa_handler != host->sa_handler || now.sa_flags != host->sa_flags))
        sigaction(SIGINT, host, NULL);
}

static int start_python(const char *exe, char *err, size_t errsize) {
    struct sigaction host_sigint;
    int have_host_sigint = sigaction(SIGINT, NULL, &host_sigint) == 0;
    /* UTF-8 mode: the isolated pre-configuration leaves it off and the locale alone, so in a host
       that never calls setlocale (the "C" locale: fmusim, fmuCheck) the filesystem encoding would
       be ASCII, and a path with "ü" in it (the unpack folder, a model_file) could not be opened.
       FMI's strings and URIs are UTF-8; everything else of the isolation stays. */
    PyPreConfig preconfig;
    P.PyPreConfig_InitIsolatedConfig(&preconfig);
    preconfig.utf8_mode = 1;
    PyStatus pre = P.Py_PreInitialize(&preconfig);
    if (P.PyStatus_Exception(pre)) {
        snprintf(err, errsize, "CPython at %s failed to pre-initialise: %s%s%s", exe, pre.func ? pre.func : "",
                 pre.func ? ": " : "", pre.err_msg ? pre.err_msg : "unknown error");
        return 0;
    }
    PyConfig config;
    P.PyConfig_InitIsolatedConfig(&config);
    config.install_signal_handlers = 0;      /* no SIGPIPE/SIGXFSZ changes; SIGINT: see below */
    /* the interpreter as if that executable ran it: a virtual environment's pyvenv.cfg is honoured */
    PyStatus st = P.PyConfig_SetBytesString(&config, &config.program_name, exe);
    if (!P.PyStatus_Exception(st)) st = P.PyConfig_SetBytesString(&config, &config.executable, exe);
    if (!P.PyStatus_Exception(st)) st = P.Py_InitializeFromConfig(&config);
    P.PyConfig_Clear(&config);
    if (P.PyStatus_Exception(st)) {
        snprintf(err, errsize, "CPython at %s failed to start: %s%s%s", exe, st.func ? st.func : "",
                 st.func ? ": " : "", st.err_msg ? st.err_msg : "unknown error");
        return 0;
    }
    import_signal_keep_hosts_sigint(&host_sigint, have_host_sigint);
    PyObject *mark = P.PyBool_FromLong(1);
    if (P.PySys_SetObject(STARTED_MARK, mark) != 0) P.PyErr_Clear();
    P.Py_DecRef(mark);
    P.PyEval_SaveThread();                   /* release the GIL; the main thread state stays */
    return 1;
}

/* Make P usable: attach to the process's interpreter, or load and start one. Once per process. */
static int ensure_python(const char *resources, char *err, size_t errsize) {
    pthread_mutex_lock(&g_python_lock);
    int ok = g_python_ready;
    if (ok) goto done;
    void *in_process = dlsym(RTLD_DEFAULT, "Py_IsInitialized");
    if (in_process && ((int (*)(void))in_process)()) {
        if (!resolve_api(RTLD_DEFAULT, err, errsize)) goto done;
        const char *ver = P.Py_GetVersion();  /* "3.11.7 (main, ...) [GCC ...]": its first word */
        /* (or to the one this binary started before it was unloaded: the bridge tells them apart by
           STARTED_MARK) */
        snprintf(g_python_note, sizeof g_python_note, "attached to the host process's Python %.*s",
                 (int)strcspn(ver, " "), ver);
        ok = g_python_ready = 1;
        goto done;
    }
    char exe[PATH_MAX] = "", lib[PATH_MAX] = "", how[256] = "";
    if (!find_interpreter(resources, exe, lib, how, err, errsize)) goto done;
    void *handle = dlopen(lib, RTLD_NOW | RTLD_GLOBAL);
    if (!handle) {
        snprintf(err, errsize, "cannot load the Python library %s: %s", lib, dlerror());
        goto done;
    }
    if (!resolve_api(handle, err, errsize)) goto done;
    char want[16];
    snprintf(want, sizeof want, "%d.%d.", CC_PY_MAJOR, CC_PY_MINOR);
    if (strncmp(P.Py_GetVersion(), want, strlen(want)) != 0) {
        snprintf(err, errsize, "%s is Python %.20s, but this FMU was built for CPython %d.%d", lib,
                 P.Py_GetVersion(), CC_PY_MAJOR, CC_PY_MINOR);
        goto done;
    }
    if (!P.Py_IsInitialized() && !start_python(exe, err, errsize)) goto done;
    const char *ver = P.Py_GetVersion();
    snprintf(g_python_note, sizeof g_python_note, "started Python %.*s from %s (%s; library %s)",
             (int)strcspn(ver, " "), ver, exe, how, lib);
    ok = g_python_ready = 1;
done:
    pthread_mutex_unlock(&g_python_lock);
    return ok;
}

/* Host threads given a Python thread state for good (see the file's header). */
#define MAX_KEPT_THREAD_STATES 64u
static unsigned g_kept_thread_states = 0;

static int keep_a_thread_state(void) {
    unsigned n = __atomic_load_n(&g_kept_thread_states, __ATOMIC_RELAXED);
    while (n < MAX_KEPT_THREAD_STATES)
        if (__atomic_compare_exchange_n(&g_kept_thread_states, &n, n + 1, 0, __ATOMIC_RELAXED, __ATOMIC_RELAXED))
            return 1;
    return 0;
}

static PyGILState_STATE gil_enter(void) {
    if (!P.PyGILState_GetThisThreadState() && keep_a_thread_state()) {
        /* a thread Python has not seen: give it a thread state for good (see the file's header);
           past the first MAX_KEPT_THREAD_STATES, the Ensure below makes one that its Release frees */
        P.PyGILState_Ensure();
        P.PyEval_SaveThread();
    }
    return P.PyGILState_Ensure();
}

/* The text of the pending exception (and clear it) */
static void take_exception(char *out, size_t size) {
    PyObject *type = NULL, *value = NULL, *tb = NULL;
    P.PyErr_Fetch(&type, &value, &tb);
    P.PyErr_NormalizeException(&type, &value, &tb);
    const char *text = NULL, *kind = NULL;
    PyObject *s = value ? P.PyObject_Str(value) : NULL;
    if (s) text = P.PyUnicode_AsUTF8(s);
    if (!text) P.PyErr_Clear();
    /* the exception's type when its text says nothing (KeyboardInterrupt(), an assert without text) */
    PyObject *k = (!text || !text[0]) && type ? P.PyObject_GetAttrString(type, "__name__") : NULL;
    if (k) kind = P.PyUnicode_AsUTF8(k);
    if (!kind) P.PyErr_Clear();
    if (kind && text) snprintf(out, size, "%s (an exception without a message)", kind);
    else if (kind) snprintf(out, size, "%s", kind);
    else snprintf(out, size, "%s", text && text[0] ? text : "unknown Python error");
    if (k) P.Py_DecRef(k);
    if (s) P.Py_DecRef(s);
    if (type) P.Py_DecRef(type);
    if (value) P.Py_DecRef(value);
    if (tb) P.Py_DecRef(tb);
}

/* Call inst.py.<method>(args...) with the GIL held; args are new references (stolen). Returns the
 * status the method returned, or fmi2Error (logged) if it raised. *result receives the return
 * value itself when not NULL (new reference). */
static fmi2Status call(Instance *inst, const char *method, PyObject **result, int nargs, ...) {
    char msg[2048];
    fmi2Status status = fmi2Error;
    PyObject *args = P.PyTuple_New(nargs);
    va_list ap;
    va_start(ap, nargs);
    for (int i = 0; i < nargs; i++) P.PyTuple_SetItem(args, i, va_arg(ap, PyObject *));
    va_end(ap);
    PyObject *fn = P.PyObject_GetAttrString(inst->py, method);
    PyObject *ret = fn ? P.PyObject_CallObject(fn, args) : NULL;
    if (fn) P.Py_DecRef(fn);
    P.Py_DecRef(args);
    if (!ret) {
        take_exception(msg, sizeof msg);
        LOGI(inst, fmi2Error, "internal error in %s: %s", method, msg);
        return fmi2Error;
    }
    if (result) {
        *result = ret;
        return fmi2OK;
    }
    long s = P.PyLong_AsLong(ret);
    P.Py_DecRef(ret);
    if (s == -1 && P.PyErr_Occurred()) {
        take_exception(msg, sizeof msg);
        LOGI(inst, fmi2Error, "internal error in %s: it returned no status (%s)", method, msg);
        return fmi2Error;
    }
    status = (s >= fmi2OK && s <= fmi2Error) ? (fmi2Status)s : fmi2Error;
    return status;
}

#define PTR(p) P.PyLong_FromVoidPtr((void *)(p))
#define SIZE(n) P.PyLong_FromSize_t((size_t)(n))

static Instance *checked(fmi2Component c) {
    Instance *inst = (Instance *)live_find(&live_instances, c);
    return (inst && inst->magic == INSTANCE_MAGIC) ? inst : NULL;
}

/* ------------------------------------------------------------------------------------------------
 * Resource location URI -> path ("file:///a/b%20c/resources" or "file:/a/b")
 */
static int uri_to_path(const char *uri, char *out, size_t size) {
    if (!uri) return 0;
    const char *p = uri;
    if (strncmp(p, "file://", 7) == 0) {
        p += 7;
        if (strncmp(p, "localhost/", 10) == 0) p += 9;
    } else if (strncmp(p, "file:", 5) == 0) {
        p += 5;
    }
    size_t j = 0;
    for (; *p && j + 1 < size; p++) {
        if (p[0] == '%' && isxdigit((unsigned char)p[1]) && isxdigit((unsigned char)p[2])) {
            char hex[3] = {p[1], p[2], 0};
            out[j++] = (char)strtol(hex, NULL, 16);
            p += 2;
        } else {
            out[j++] = *p;
        }
    }
    while (j > 1 && out[j - 1] == '/') j--;
    out[j] = 0;
    return j > 0;
}

/* ------------------------------------------------------------------------------------------------
 * FMI 2.0: inquiry, instantiation
 */
FMI2_Export const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
FMI2_Export const char *fmi2GetVersion(void) { return fmi2Version; }

static long attr_long(PyObject *obj, const char *name, int *ok) {
    PyObject *v = P.PyObject_GetAttrString(obj, name);
    if (!v) {
        *ok = 0;
        return 0;
    }
    long x = P.PyLong_AsLong(v);
    P.Py_DecRef(v);
    if (x == -1 && P.PyErr_Occurred()) *ok = 0;
    return x;
}

static void *attr_ptr(PyObject *obj, const char *name, int *ok) {
    PyObject *v = P.PyObject_GetAttrString(obj, name);
    if (!v) {
        *ok = 0;
        return NULL;
    }
    void *x = P.PyLong_AsVoidPtr(v);
    P.Py_DecRef(v);
    if (!x) *ok = 0;
    return x;
}

/* The bridge module of this FMU (by GUID): resources/cablecasing_fmi2_bridge.py, imported once per
 * process and FMU build, so what it keeps (the imported model code) serves every instance */
static const char *BOOTSTRAP =
    "def _load(resources, guid):\n"
    "    import importlib.util, os, sys\n"
    "    name = '_cablecasing_fmi2_bridge_' + ''.join(c if c.isalnum() else '_' for c in guid)\n"
    "    mod = sys.modules.get(name)\n"
    "    if mod is None:\n"
    "        path = os.path.join(resources, 'cablecasing_fmi2_bridge.py')\n"
    "        spec = importlib.util.spec_from_file_location(name, path)\n"
    "        mod = importlib.util.module_from_spec(spec)\n"
    "        spec.loader.exec_module(mod)\n"
    "        sys.modules[name] = mod\n"
    "    return mod\n";

FMI2_Export fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                                          fmi2String fmuResourceLocation,
                                          const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                                          fmi2Boolean loggingOn) {
    const char *name = instanceName ? instanceName : "";
    char err[4096], resources[PATH_MAX];
    if (!functions) {
        fprintf(stderr, "[CableCasing ERROR] fmi2Instantiate: no callback functions given\n");
        return NULL;
    }
    if (fmuType != fmi2CoSimulation) {
        logf_to_host(functions, name, SHOW_ALL, fmi2Error, 0,
                     "fmi2Instantiate: CableCasing is a co-simulation FMU (fmi2CoSimulation); model exchange "
                     "is not provided");
        return NULL;
    }
    if (!uri_to_path(fmuResourceLocation, resources, sizeof resources)) {
        logf_to_host(functions, name, SHOW_ALL, fmi2Error, 1,
                     "fmi2Instantiate: fmuResourceLocation %s is not a file: URI of the FMU's resources folder",
                     fmuResourceLocation ? fmuResourceLocation : "(NULL)");
        return NULL;
    }
    if (!ensure_python(resources, err, sizeof err)) {
        logf_to_host(functions, name, SHOW_ALL, fmi2Error, 1, "CableCasing.fmu cannot start Python: %s", err);
        return NULL;
    }
    Instance *inst = calloc(1, sizeof *inst);
    if (!inst) return NULL;
    inst->magic = INSTANCE_MAGIC;
    inst->cb = *functions;
    snprintf(inst->name, sizeof inst->name, "%s", name);
    /* warnings and discards whatever loggingOn: a user must see why a step was discarded (docs/fmu.md,
       "Messages you may see"); fmi2SetDebugLogging switches them off by their categories */
    inst->log_shown = SHOW_WARNING | SHOW_DISCARD | (loggingOn ? SHOW_INFO : 0u);
    inst->state = S_INSTANTIATED;

    PyGILState_STATE gil = gil_enter();
    PyObject *globals = P.PyDict_New(), *mod = NULL, *ret = NULL;
    int ok = 1;
    P.PyDict_SetItemString(globals, "__builtins__", P.PyEval_GetBuiltins());
    ret = P.PyRun_StringFlags(BOOTSTRAP, Py_file_input, globals, globals, NULL);
    if (ret) {
        P.Py_DecRef(ret);
        PyObject *load = P.PyDict_GetItemString(globals, "_load"); /* borrowed */
        PyObject *args = P.PyTuple_New(2);
        P.PyTuple_SetItem(args, 0, P.PyUnicode_FromString(resources));
        P.PyTuple_SetItem(args, 1, P.PyUnicode_FromString(fmuGUID ? fmuGUID : ""));
        mod = P.PyObject_CallObject(load, args);
        P.Py_DecRef(args);
    }
    if (!mod) {
        take_exception(err, sizeof err);
        logf_to_host(functions, name, SHOW_ALL, fmi2Error, 1, "CableCasing.fmu cannot load its bridge from %s: %s",
                     resources, err);
        ok = 0;
    } else {
        PyObject *cls = P.PyObject_GetAttrString(mod, "Instance");
        PyObject *args = P.PyTuple_New(9);
        P.PyTuple_SetItem(args, 0, P.PyUnicode_FromString(name));
        P.PyTuple_SetItem(args, 1, P.PyUnicode_FromString(fmuGUID ? fmuGUID : ""));
        P.PyTuple_SetItem(args, 2, P.PyUnicode_FromString(resources));
        P.PyTuple_SetItem(args, 3, P.PyBool_FromLong(visible));
        P.PyTuple_SetItem(args, 4, P.PyBool_FromLong(loggingOn));
        P.PyTuple_SetItem(args, 5, PTR(&bridge_log));
        P.PyTuple_SetItem(args, 6, PTR(inst));
        P.PyTuple_SetItem(args, 7, P.PyUnicode_FromString(g_python_note));
        P.PyTuple_SetItem(args, 8, P.PyUnicode_FromString(fmi2Version));
        inst->py = cls ? P.PyObject_CallObject(cls, args) : NULL;
        P.Py_DecRef(args);
        if (cls) P.Py_DecRef(cls);
        P.Py_DecRef(mod);
        if (!inst->py) {
            take_exception(err, sizeof err);
            /* the reason (a missing package, a wrong GUID, ...): the bridge raised FMUStartError with it
             * and logs nothing itself, so it is said once, here, to the host and to stderr */
            logf_to_host(functions, name, SHOW_ALL, fmi2Error, 1, "CableCasing.fmu cannot be instantiated: %s", err);
            ok = 0;
        }
    }
    if (ok) {
        inst->inputs = attr_ptr(inst->py, "input_address", &ok);
        inst->outputs = attr_ptr(inst->py, "output_address", &ok);
        inst->in0 = (fmi2ValueReference)attr_long(inst->py, "input_vr0", &ok);
        inst->nin = (fmi2ValueReference)attr_long(inst->py, "input_count", &ok);
        inst->out0 = (fmi2ValueReference)attr_long(inst->py, "output_vr0", &ok);
        inst->nout = (fmi2ValueReference)attr_long(inst->py, "output_count", &ok);
        long nint = attr_long(inst->py, "integer_output_count", &ok);
        inst->nint = (ok && nint >= 0 && nint <= MAX_INT_OUTPUTS) ? (size_t)nint : 0;
        for (size_t k = 0; ok && k < inst->nint; k++) {
            char key[32];
            snprintf(key, sizeof key, "integer_output_vr%zu", k);
            inst->int_vr[k] = (fmi2ValueReference)attr_long(inst->py, key, &ok);
            inst->int_idx[k] = inst->int_vr[k] - inst->out0;
        }
        inst->m_do_step = P.PyObject_GetAttrString(inst->py, "do_step");
        inst->slave = inst->m_do_step ? P.PyObject_GetAttrString(inst->m_do_step, "__self__") : NULL;
        if (inst->slave) inst->clock_only_seen = attr_long(inst->slave, "clock_only_calls", &ok);
        if (!ok || !inst->m_do_step || !inst->slave) {
            take_exception(err, sizeof err);
            logf_to_host(functions, name, SHOW_ALL, fmi2Error, 1, "CableCasing.fmu: the bridge is incomplete (%s)", err);
            ok = 0;
        }
    }
    if (!ok) {
        if (inst->slave) P.Py_DecRef(inst->slave);
        if (inst->m_do_step) P.Py_DecRef(inst->m_do_step);
        if (inst->py) P.Py_DecRef(inst->py);
    }
    P.Py_DecRef(globals);
    P.PyGILState_Release(gil);
    if (!ok) {
        inst->magic = 0;
        free(inst);
        return NULL;
    }
    return live_add(&live_instances, &inst->live);
}

static void free_states_of(const Instance *inst);

FMI2_Export void fmi2FreeInstance(fmi2Component c) {
    Instance *inst = checked(c);
    if (!inst) return;
    live_remove(&live_instances, &inst->live);
    PyGILState_STATE gil = gil_enter();
    free_states_of(inst);   /* FMI 2.0, fmi2FreeInstance: all memory its functions allocated, its states too */
    call(inst, "free", NULL, 0);
    P.Py_DecRef(inst->m_do_step);
    if (inst->slave) P.Py_DecRef(inst->slave);
    P.Py_DecRef(inst->py);
    P.PyGILState_Release(gil);
    inst->magic = 0;
    free(inst);
}

#define ENTER(c)                                                                                       \
    Instance *inst = checked(c);                                                                       \
    if (!inst) return fmi2Error;

static fmi2Status call0(Instance *inst, const char *method) {
    PyGILState_STATE gil = gil_enter();
    fmi2Status s = call(inst, method, NULL, 0);
    P.PyGILState_Release(gil);
    return s;
}

/* A NULL where the host's variable or buffer belongs (``what``): fmi2Error with a message naming the call
 * and the argument, in every state of the life cycle, and nothing read or written */
static fmi2Status null_argument(Instance *inst, const char *call, const char *argument, const char *what) {
    LOGI(inst, fmi2Error, "%s: the argument %s is NULL, where %s belongs; nothing done", call, argument, what);
    return fmi2Error;
}

/* Whether ``call``'s arrays of ``nvr`` value references and values are refused for a NULL (logged) */
static int null_arrays(Instance *inst, const char *call, const fmi2ValueReference vr[], size_t nvr,
                       const void *value) {
    if (nvr == 0 || (vr && value)) return 0;
    int both = !vr && !value;
    LOGI(inst, fmi2Error, "%s: the argument%s NULL, where the array%s of nvr = %zu %s belong%s; nothing done", call,
         both ? "s vr and value are" : !vr ? " vr is" : " value is", both ? "s" : "", nvr,
         both ? "value references and values" : !vr ? "value references" : "values", both ? "" : "s");
    return 1;
}

/* a call that the life cycle does not allow: fmi2Error with a message */
static fmi2Status refuse(Instance *inst, const char *what) {
    static const char *states[] = {"instantiated (before fmi2EnterInitializationMode)", "in initialization mode",
                                   "initialised (stepping)", "terminated (after fmi2Terminate)"};
    LOGI(inst, fmi2Error, "%s is not allowed when the FMU is %s", what, states[inst->state]);
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                                           const fmi2String categories[]) {
    ENTER(c);
    /* The modelDescription's <LogCategories>, each the messages of one status (docs/fmu.md, "Messages
     * you may see"): loggingOn switches the listed categories on or off, and leaves the others as they
     * are (as the FMU SDK and the Reference FMUs do). logStatusError and logStatusFatal are accepted but
     * change nothing: errors are always logged (FMI 2.0, 2.1.3: "logger was called" for every fmi2Error).
     * With no category loggingOn switches logAll, the informational messages, only: warnings and
     * discards stay as they are, so that a host that turns "debug logging" off still sees why a step
     * was discarded (FMI 2.0.x, 2.1.5, says all categories: a deviation, documented). An unknown or
     * NULL category is an error, naming it, and changes nothing. */
    static const char *known[] = {"logAll", "logStatusWarning", "logStatusDiscard", "logStatusError",
                                  "logStatusFatal", NULL};
    static const unsigned shows[] = {SHOW_INFO, SHOW_WARNING, SHOW_DISCARD, 0u, 0u};
    if (nCategories > 0 && !categories) {
        LOGI(inst, fmi2Error, "fmi2SetDebugLogging: nCategories = %zu but categories = NULL; logging unchanged",
             nCategories);
        return fmi2Error;
    }
    unsigned switched = nCategories == 0 ? SHOW_INFO : 0u;
    for (size_t i = 0; i < nCategories; i++) {
        const char *name = categories[i];
        int k = 0;
        while (known[k] && !(name && strcmp(name, known[k]) == 0)) k++;
        if (!known[k]) {
            LOGI(inst, fmi2Error,
                 "fmi2SetDebugLogging: category %s%.200s%s is not one of this FMU's (logAll, logStatusWarning, "
                 "logStatusDiscard, logStatusError, logStatusFatal: the modelDescription's LogCategories); "
                 "logging unchanged",
                 name ? "'" : "", name ? name : "NULL", name ? "'" : "");
            return fmi2Error;
        }
        switched |= shows[k];
    }
    if (loggingOn) inst->log_shown |= switched;
    else inst->log_shown &= ~switched;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                                           fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    ENTER(c);
    if (inst->state != S_INSTANTIATED) return refuse(inst, "fmi2SetupExperiment");
    PyGILState_STATE gil = gil_enter();
    fmi2Status s = call(inst, "setup_experiment", NULL, 5, P.PyBool_FromLong(toleranceDefined),
                        P.PyFloat_FromDouble(tolerance), P.PyFloat_FromDouble(startTime),
                        P.PyBool_FromLong(stopTimeDefined), P.PyFloat_FromDouble(stopTime));
    P.PyGILState_Release(gil);
    return s;
}

FMI2_Export fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    ENTER(c);
    if (inst->state != S_INSTANTIATED) return refuse(inst, "fmi2EnterInitializationMode");
    fmi2Status s = call0(inst, "enter_initialization_mode");
    if (s <= fmi2Warning) inst->state = S_INITIALIZATION;
    return s;
}

FMI2_Export fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    ENTER(c);
    if (inst->state != S_INITIALIZATION) return refuse(inst, "fmi2ExitInitializationMode");
    fmi2Status s = call0(inst, "exit_initialization_mode");
    inst->state = S_STEPPING;   /* also after an error: doStep then says why it cannot step */
    return s;
}

FMI2_Export fmi2Status fmi2Terminate(fmi2Component c) {
    ENTER(c);
    if (inst->state != S_STEPPING) return refuse(inst, "fmi2Terminate");
    if (inst->step_calls > 0) { /* where a co-simulation's time went: in the FMU's steps or in the host */
        double wall = monotonic_seconds() - inst->first_step_at;
        LOGI(inst, fmi2OK,
             "%ld doStep calls took %.3f s inside the FMU (%.1f us per call); %.3f s passed from the first "
             "call to fmi2Terminate, so the host spent %.3f s (%.1f us per call) between them",
             inst->step_calls, inst->step_seconds, 1e6 * inst->step_seconds / inst->step_calls, wall,
             wall - inst->step_seconds, 1e6 * (wall - inst->step_seconds) / inst->step_calls);
        LOGI(inst, fmi2OK,
             "real time: the longest doStep call took %.3f ms (from t = %.9g s); %ld of %ld calls took longer "
             "than their communication step (a real-time master would have missed their deadlines)",
             1e3 * inst->longest_step, inst->longest_step_at, inst->late_calls, inst->step_calls);
    }
    fmi2Status s = call0(inst, "terminate");
    inst->state = S_TERMINATED;
    return s;
}

FMI2_Export fmi2Status fmi2Reset(fmi2Component c) {
    ENTER(c);
    fmi2Status s = call0(inst, "reset");
    if (s <= fmi2Warning) inst->state = S_INSTANTIATED;
    inst->step_calls = 0;
    inst->step_seconds = 0.0;
    inst->longest_step = 0.0;
    inst->late_calls = 0;
    return s;
}

/* ------------------------------------------------------------------------------------------------
 * Variables: the support inputs and the outputs in C, everything else through Python
 */
#define VR_ARGS(vr, nvr, values) PTR(vr), SIZE(nvr), PTR(values)

static fmi2Status slow_access(Instance *inst, const char *method, const fmi2ValueReference vr[], size_t nvr,
                              const void *values) {
    if (nvr == 0) return fmi2OK;   /* (a NULL array with nvr > 0 is refused before: null_arrays) */
    PyGILState_STATE gil = gil_enter();
    fmi2Status s = call(inst, method, NULL, 3, VR_ARGS(vr, nvr, values));
    P.PyGILState_Release(gil);
    return s;
}

static int setters_allowed(Instance *inst) { return inst->state != S_TERMINATED; }

/* FMI 2.0, 4.2.4: no fmi2Get* before fmi2EnterInitializationMode (there is no value yet) */
static int getters_allowed(Instance *inst) { return inst->state != S_INSTANTIATED; }

/* In Initialization Mode the outputs are computed from the parameters set so far: through Python */
FMI2_Export fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    ENTER(c);
    if (null_arrays(inst, "fmi2GetReal", vr, nvr, value)) return fmi2Error;
    if (!getters_allowed(inst)) return refuse(inst, "fmi2GetReal");
    size_t i = 0;
    if (inst->state == S_INITIALIZATION)
        return slow_access(inst, "get_real", vr, nvr, value);
    for (; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        if (r - inst->out0 < inst->nout) {
            int integer = 0;
            for (size_t k = 0; k < inst->nint; k++) integer |= (r == inst->int_vr[k]);
            if (integer) break;
            value[i] = inst->outputs[r - inst->out0];
        } else if (r - inst->in0 < inst->nin) {
            value[i] = inst->inputs[r - inst->in0];
        } else {
            break;
        }
    }
    if (i == nvr) return fmi2OK;
    return slow_access(inst, "get_real", vr, nvr, value);   /* parameters, or a wrong reference */
}

FMI2_Export fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                   const fmi2Real value[]) {
    ENTER(c);
    if (null_arrays(inst, "fmi2SetReal", vr, nvr, value)) return fmi2Error;
    if (!setters_allowed(inst)) return refuse(inst, "fmi2SetReal");
    size_t i = 0;
    for (; i < nvr && vr[i] - inst->in0 < inst->nin; i++) inst->inputs[vr[i] - inst->in0] = value[i];
    if (i == nvr) return fmi2OK;
    return slow_access(inst, "set_real", vr, nvr, value);
}

FMI2_Export fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      fmi2Integer value[]) {
    ENTER(c);
    if (null_arrays(inst, "fmi2GetInteger", vr, nvr, value)) return fmi2Error;
    if (!getters_allowed(inst)) return refuse(inst, "fmi2GetInteger");
    size_t i = 0;
    if (inst->state == S_INITIALIZATION)
        return slow_access(inst, "get_integer", vr, nvr, value);
    for (; i < nvr; i++) {
        size_t k = 0;
        while (k < inst->nint && vr[i] != inst->int_vr[k]) k++;
        if (k == inst->nint) break;
        value[i] = (fmi2Integer)inst->outputs[inst->int_idx[k]];
    }
    if (i == nvr) return fmi2OK;
    return slow_access(inst, "get_integer", vr, nvr, value);
}

FMI2_Export fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      const fmi2Integer value[]) {
    ENTER(c);
    if (null_arrays(inst, "fmi2SetInteger", vr, nvr, value)) return fmi2Error;
    if (!setters_allowed(inst)) return refuse(inst, "fmi2SetInteger");
    return slow_access(inst, "set_integer", vr, nvr, value);
}

FMI2_Export fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      fmi2Boolean value[]) {
    ENTER(c);
    if (null_arrays(inst, "fmi2GetBoolean", vr, nvr, value)) return fmi2Error;
    if (!getters_allowed(inst)) return refuse(inst, "fmi2GetBoolean");
    return slow_access(inst, "get_boolean", vr, nvr, value);
}

FMI2_Export fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                      const fmi2Boolean value[]) {
    ENTER(c);
    if (null_arrays(inst, "fmi2SetBoolean", vr, nvr, value)) return fmi2Error;
    if (!setters_allowed(inst)) return refuse(inst, "fmi2SetBoolean");
    return slow_access(inst, "set_boolean", vr, nvr, value);
}

FMI2_Export fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     fmi2String value[]) {
    ENTER(c);
    if (null_arrays(inst, "fmi2GetString", vr, nvr, value)) return fmi2Error;
    if (!getters_allowed(inst)) return refuse(inst, "fmi2GetString");
    return slow_access(inst, "get_string", vr, nvr, value);
}

FMI2_Export fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     const fmi2String value[]) {
    ENTER(c);
    if (null_arrays(inst, "fmi2SetString", vr, nvr, value)) return fmi2Error;
    if (!setters_allowed(inst)) return refuse(inst, "fmi2SetString");
    return slow_access(inst, "set_string", vr, nvr, value);
}

/* ------------------------------------------------------------------------------------------------
 * FMU state
 */
/* States and the GIL: a state is looked up, and unlinked and freed, only with the GIL held, so one that a
 * call found stays valid while that call holds the GIL (another thread's fmi2FreeInstance of its maker,
 * or fmi2FreeFMUstate, waits for the GIL to free it). A call into Python (call()) may release the GIL in
 * between: what is needed of a state is taken before (a reference to its Python object), and the state
 * is looked up again after, never used through the pointer found before. */

/* The state whose handle is ``s``, or NULL (logged); with the GIL held */
static State *checked_state(Instance *inst, const char *what, fmi2FMUstate s) {
    if (!s) {   /* (review BF4: the argument named, not a handle "(nil)" said to be another FMU's) */
        LOGI(inst, fmi2Error, "%s: the argument FMUstate is NULL, where a state fmi2GetFMUstate made belongs; "
             "nothing done", what);
        return NULL;
    }
    State *st = (State *)live_find(&live_states, s);
    if (!st)
        LOGI(inst, fmi2Error,
             "%s: the FMU state %p was not made by this FMU (or was freed, by fmi2FreeFMUstate or with its instance)",
             what, s);
    return st;
}

/* Unlink and free ``st``; with the GIL held. Unlinked first: no other call finds it from then on (the
 * decrefs may run Python code, which may let another thread run). */
static void free_state(State *st) {
    live_remove(&live_states, &st->live);
    P.Py_DecRef(st->state);
    if (st->bytes) P.Py_DecRef(st->bytes);
    st->magic = 0;
    free(st);
}

/* Free every state ``inst`` owns (fmi2FreeInstance), with the GIL held: their handles are refused from
 * then on, as freed states' are. A state of another instance set into ``inst`` stays its maker's. */
static void free_states_of(const Instance *inst) {
    for (;;) {
        State *mine = NULL;
        pthread_mutex_lock(&live_lock);
        for (Live *l = live_states; l && !mine; l = l->next)
            if (((State *)l)->owner == inst) mine = (State *)l;
        pthread_mutex_unlock(&live_lock);
        if (!mine) return;
        free_state(mine);
    }
}

/* A new FMU state of ``inst`` holding the Python state ``obj`` (its reference taken), its handle put
 * into *FMUstate; with the GIL held. fmi2Error, ``obj`` released, when it cannot be allocated. */
static fmi2Status new_state(Instance *inst, PyObject *obj, fmi2FMUstate *FMUstate) {
    State *st = calloc(1, sizeof *st);
    if (!st) {
        P.Py_DecRef(obj);
        return fmi2Error;
    }
    st->magic = STATE_MAGIC;
    st->owner = inst;
    st->state = obj;
    *FMUstate = live_add(&live_states, &st->live);
    return fmi2OK;
}

/* Whether ``call``'s FMUstate argument, where the address of the host's fmi2FMUstate variable
 * belongs, is a state (one of the FMU's handles): refused with a log line, never read through */
static int state_where_its_address_belongs(Instance *inst, const char *call, const void *FMUstate) {
    if (!is_handle(FMUstate)) return 0;
    LOGI(inst, fmi2Error, "%s: its FMUstate argument is a state (%p), where the address of the host's "
         "fmi2FMUstate variable belongs", call, FMUstate);
    return 1;
}

static fmi2Status query(Instance *inst, const char *method, fmi2Real *number, fmi2Boolean *truth);

FMI2_Export fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    ENTER(c);
    if (!FMUstate)
        return null_argument(inst, "fmi2GetFMUstate", "FMUstate", "the address of the host's fmi2FMUstate variable");
    if (state_where_its_address_belongs(inst, "fmi2GetFMUstate", FMUstate)) return fmi2Error;
    PyObject *obj = NULL;
    PyGILState_STATE gil = gil_enter();
    fmi2Status s = call(inst, "get_state", &obj, 0);
    State *st = *FMUstate ? (State *)live_find(&live_states, *FMUstate) : NULL;
    if (s == fmi2OK && st) {   /* update the host's earlier state in place: now this instance's */
        PyObject *old = st->state, *old_bytes = st->bytes;
        st->state = obj;           /* (before the decrefs, which may run Python code: see free_state) */
        st->bytes = NULL;
        st->owner = inst;
        P.Py_DecRef(old);
        if (old_bytes) P.Py_DecRef(old_bytes);
    } else if (s == fmi2OK) {
        s = new_state(inst, obj, FMUstate);
    }
    P.PyGILState_Release(gil);
    return s;
}

FMI2_Export fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate) {
    ENTER(c);
    PyGILState_STATE gil = gil_enter();
    State *st = checked_state(inst, "fmi2SetFMUstate", FMUstate);
    if (!st) {
        P.PyGILState_Release(gil);
        return fmi2Error;
    }
    P.Py_IncRef(st->state);   /* (the call's own reference: the state may be freed while it runs) */
    fmi2Status s = call(inst, "set_state", NULL, 1, st->state);
    P.PyGILState_Release(gil);
    if (s <= fmi2Warning) {   /* the phase the state was saved in (FMI 2.0, 2.1.8): the slave's */
        fmi2Real phase = S_STEPPING;
        if (query(inst, "phase", &phase, NULL) == fmi2OK && phase >= S_INSTANTIATED && phase <= S_TERMINATED)
            inst->state = (int)phase;
        else
            inst->state = S_STEPPING;
    }
    return s;
}

static fmi2Status free_fmu_state(Instance *inst, fmi2FMUstate *FMUstate) {
    if (!FMUstate) return fmi2OK;
    State *itself = (State *)live_find(&live_states, FMUstate);
    if (itself) {
        /* the state itself where its address belongs (fmusim 0.0.39's state files): it is freed as
         * asked, and the host's copy of the handle, which cannot be reached, is left as it is */
        free_state(itself);
        return fmi2OK;
    }
    if (is_handle(FMUstate)) {   /* a handle of a state freed before, or another FMU's: not read */
        LOGI(inst, fmi2Error,
             "fmi2FreeFMUstate: the FMU state %p was not made by this FMU (or was freed, by fmi2FreeFMUstate or "
             "with its instance)",
             (void *)FMUstate);
        return fmi2Error;
    }
    if (!*FMUstate) return fmi2OK;
    State *st = checked_state(inst, "fmi2FreeFMUstate", *FMUstate);
    if (!st) return fmi2Error;
    free_state(st);
    *FMUstate = NULL;
    return fmi2OK;
}

FMI2_Export fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    ENTER(c);
    PyGILState_STATE gil = gil_enter();   /* (looked up and freed under it: see checked_state) */
    fmi2Status s = free_fmu_state(inst, FMUstate);
    P.PyGILState_Release(gil);
    return s;
}

/* The serialization of the state whose handle is ``FMUstate`` (a new reference), or NULL with *status
 * not fmi2OK (logged); with the GIL held. Kept with the state while the host asks for size then data. */
static PyObject *state_bytes(Instance *inst, const char *what, fmi2FMUstate FMUstate, fmi2Status *status) {
    State *st = checked_state(inst, what, FMUstate);
    *status = st ? fmi2OK : fmi2Error;
    if (!st) return NULL;
    if (st->bytes) {
        P.Py_IncRef(st->bytes);
        return st->bytes;
    }
    PyObject *obj = st->state, *bytes = NULL;
    P.Py_IncRef(obj);   /* (ours, compared below) */
    P.Py_IncRef(obj);   /* (the call's) */
    *status = call(inst, "serialize_state", &bytes, 1, obj);
    /* the call may have let another thread free or update the state: it is looked up again */
    st = *status == fmi2OK ? (State *)live_find(&live_states, FMUstate) : NULL;
    if (st && !st->bytes && st->state == obj) {
        P.Py_IncRef(bytes);
        st->bytes = bytes;
    }
    P.Py_DecRef(obj);
    return *status == fmi2OK ? bytes : NULL;
}

FMI2_Export fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size) {
    ENTER(c);
    if (!size) return null_argument(inst, "fmi2SerializedFMUstateSize", "size", "the address of the host's size_t variable");
    fmi2Status s;
    PyGILState_STATE gil = gil_enter();
    PyObject *bytes = state_bytes(inst, "fmi2SerializedFMUstateSize", FMUstate, &s);
    if (bytes) {
        *size = (size_t)P.PyBytes_Size(bytes);
        P.Py_DecRef(bytes);
    }
    P.PyGILState_Release(gil);
    return s;
}

FMI2_Export fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[],
                                             size_t size) {
    ENTER(c);
    if (!serializedState)
        return null_argument(inst, "fmi2SerializeFMUstate", "serializedState",
                             "a buffer of the fmi2SerializedFMUstateSize bytes");
    fmi2Status s;
    PyGILState_STATE gil = gil_enter();
    PyObject *bytes = state_bytes(inst, "fmi2SerializeFMUstate", FMUstate, &s);
    if (bytes) {
        size_t n = (size_t)P.PyBytes_Size(bytes);
        if (size < n) {
            LOGI(inst, fmi2Error, "fmi2SerializeFMUstate: the buffer holds %zu bytes, the state needs %zu "
                 "(ask fmi2SerializedFMUstateSize)", size, n);
            s = fmi2Error;
        } else {
            memcpy(serializedState, P.PyBytes_AsString(bytes), n);
        }
        P.Py_DecRef(bytes);
    }
    P.PyGILState_Release(gil);
    return s;
}

FMI2_Export fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                               fmi2FMUstate *FMUstate) {
    ENTER(c);
    if (!serializedState && size)
        return null_argument(inst, "fmi2DeSerializeFMUstate", "serializedState",
                             "a buffer of the serialised state's size bytes");
    if (!FMUstate)
        return null_argument(inst, "fmi2DeSerializeFMUstate", "FMUstate", "the address of the host's fmi2FMUstate variable");
    if (state_where_its_address_belongs(inst, "fmi2DeSerializeFMUstate", FMUstate)) return fmi2Error;
    PyObject *obj = NULL;
    PyGILState_STATE gil = gil_enter();
    fmi2Status s = call(inst, "deserialize_state", &obj, 1,
                        P.PyBytes_FromStringAndSize((const char *)serializedState, (Py_ssize_t)size));
    P.PyGILState_Release(gil);
    if (s != fmi2OK) return s;
    /* the bridge returns a false value for bytes that are not a state (and has logged why) */
    gil = gil_enter();
    if (!P.PyObject_IsTrue(obj)) {
        P.Py_DecRef(obj);
        s = fmi2Error;
    } else {
        s = new_state(inst, obj, FMUstate);
    }
    P.PyGILState_Release(gil);
    return s;
}

FMI2_Export fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[],
                                                    size_t nUnknown, const fmi2ValueReference vKnown_ref[],
                                                    size_t nKnown, const fmi2Real dvKnown[], fmi2Real dvUnknown[]) {
    ENTER(c);
    (void)vUnknown_ref, (void)nUnknown, (void)vKnown_ref, (void)nKnown, (void)dvKnown, (void)dvUnknown;
    LOGI(inst, fmi2Error, "fmi2GetDirectionalDerivative is not provided (providesDirectionalDerivative=false)");
    return fmi2Error;
}

/* ------------------------------------------------------------------------------------------------
 * Co-simulation
 */
FMI2_Export fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                                   const fmi2Integer order[], const fmi2Real value[]) {
    ENTER(c);
    (void)vr, (void)nvr, (void)order, (void)value;
    LOGI(inst, fmi2Error,
         "fmi2SetRealInputDerivatives is not provided (canInterpolateInputs=false): connect the velocity and "
         "acceleration inputs (<body>.<support>.v* and .a*) instead");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                                    const fmi2Integer order[], fmi2Real value[]) {
    ENTER(c);
    (void)vr, (void)nvr, (void)order, (void)value;
    LOGI(inst, fmi2Error, "fmi2GetRealOutputDerivatives is not provided (maxOutputDerivativeOrder=0)");
    return fmi2Error;
}

FMI2_Export fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                                  fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    ENTER(c);
    (void)noSetFMUStatePriorToCurrentPoint;
    if (inst->state != S_STEPPING) return refuse(inst, "fmi2DoStep");
    double t_enter = monotonic_seconds();
    PyGILState_STATE gil = gil_enter();
    PyObject *args[2] = {P.PyFloat_FromDouble(currentCommunicationPoint),
                         P.PyFloat_FromDouble(communicationStepSize)};
    PyObject *tuple = P.PyTuple_New(2);
    P.PyTuple_SetItem(tuple, 0, args[0]);
    P.PyTuple_SetItem(tuple, 1, args[1]);
    PyObject *ret = P.PyObject_CallObject(inst->m_do_step, tuple);
    P.Py_DecRef(tuple);
    fmi2Status s;
    int clock_only = 0;
    if (!ret) {
        char msg[2048];
        take_exception(msg, sizeof msg);
        LOGI(inst, fmi2Error, "internal error in doStep: %s", msg);
        s = fmi2Error;
    } else {
        long v = P.PyLong_AsLong(ret);
        P.Py_DecRef(ret);
        s = (v >= fmi2OK && v <= fmi2Error) ? (fmi2Status)v : fmi2Error;
        if (s <= fmi2Warning) {   /* a step within the rounding of a clock: the slave counts those */
            int ok = 1;
            long n = attr_long(inst->slave, "clock_only_calls", &ok);
            if (!ok) P.PyErr_Clear();
            clock_only = ok && n != inst->clock_only_seen;
            if (ok) inst->clock_only_seen = n;
        }
    }
    P.PyGILState_Release(gil);
    /* the timing and real-time report counts the steps taken, not the calls refused (a step of 0 or
     * less, at the wrong time, past stopTime, discarded) nor those that only moved the clock (a step
     * within 1e-6 solver.dt: no step): their wall time is no step's, and any of it exceeds such a step */
    if (s <= fmi2Warning && !clock_only) {
        double took = monotonic_seconds() - t_enter;
        if (inst->step_calls == 0) inst->first_step_at = t_enter;
        inst->step_calls += 1;
        inst->step_seconds += took;
        if (took > inst->longest_step) {
            inst->longest_step = took;
            inst->longest_step_at = currentCommunicationPoint;
        }
        if (took > communicationStepSize) inst->late_calls += 1; /* a real-time master's missed deadline */
    }
    return s;
}

FMI2_Export fmi2Status fmi2CancelStep(fmi2Component c) {
    ENTER(c);
    LOGI(inst, fmi2Error, "fmi2CancelStep: doStep never runs asynchronously (canRunAsynchronuously=false)");
    return fmi2Error;
}

/* The status functions answer in every state after fmi2Instantiate, where FMI 2.0.x, 4.2.4, allows them only
 * after initialisation (stepComplete, stepFailed, terminated): the answers are true of an instance that has
 * not stepped (no step pending; fmi2LastSuccessfulTime the startTime set so far, 0 before
 * fmi2SetupExperiment; not terminated), so a master that asks early is answered, not refused
 * (docs/fmu.md, "Statuses for careless masters"). A NULL value is refused first, in every state. */
#define STATUS_VALUE(call, type)                                                                       \
    if (!value) return null_argument(inst, call, "value", "the address of the host's " type " variable")

FMI2_Export fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    ENTER(c);
    STATUS_VALUE("fmi2GetStatus", "fmi2Status");
    if (s == fmi2DoStepStatus) {
        *value = fmi2OK;   /* doStep is synchronous: never pending */
        return fmi2OK;
    }
    LOGI(inst, fmi2Discard, "fmi2GetStatus: status kind %d is not available (only fmi2DoStepStatus)", (int)s);
    return fmi2Discard;
}

/* A status from the bridge's method of no arguments: its result as a number, or as a truth value. */
static fmi2Status query(Instance *inst, const char *method, fmi2Real *number, fmi2Boolean *truth) {
    PyObject *r = NULL;
    PyGILState_STATE gil = gil_enter();
    fmi2Status st = call(inst, method, &r, 0);
    if (st == fmi2OK) {
        if (number) *number = P.PyFloat_AsDouble(r);
        if (truth) *truth = P.PyObject_IsTrue(r) > 0 ? fmi2True : fmi2False;
        P.Py_DecRef(r);
    }
    P.PyGILState_Release(gil);
    return st;
}

FMI2_Export fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    ENTER(c);
    STATUS_VALUE("fmi2GetRealStatus", "fmi2Real");
    if (s != fmi2LastSuccessfulTime) {
        LOGI(inst, fmi2Discard, "fmi2GetRealStatus: status kind %d is not available (only fmi2LastSuccessfulTime)",
             (int)s);
        return fmi2Discard;
    }
    return query(inst, "last_successful_time", value, NULL);
}

FMI2_Export fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    ENTER(c);
    STATUS_VALUE("fmi2GetIntegerStatus", "fmi2Integer");
    (void)s;
    LOGI(inst, fmi2Discard, "fmi2GetIntegerStatus: no integer status is available");
    return fmi2Discard;
}

FMI2_Export fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    ENTER(c);
    STATUS_VALUE("fmi2GetBooleanStatus", "fmi2Boolean");
    if (s == fmi2Terminated) {
        /* true once a discarded step was asked for again with the same inputs (CableCasing._discard) */
        return query(inst, "terminated", NULL, value);
    }
    LOGI(inst, fmi2Discard, "fmi2GetBooleanStatus: status kind %d is not available (only fmi2Terminated)", (int)s);
    return fmi2Discard;
}

FMI2_Export fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    ENTER(c);
    STATUS_VALUE("fmi2GetStringStatus", "fmi2String");
    (void)s;
    LOGI(inst, fmi2Discard, "fmi2GetStringStatus: no string status is available (doStep is synchronous)");
    return fmi2Discard;
}
