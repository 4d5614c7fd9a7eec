/*
 * towcable FMU loader: the binaries/linux64/<model>.so of the towcable FMUs.
 *
 * pythonfmu 0.7's library (kept beside this one as libpythonfmu-export.so) serves the
 * FMI calls with Python but does not link libpython, drops every log message when the
 * host turned logging off, and returns fmi2OK from a call whose Python code reported an
 * error. This layer exports the FMI 2.0 Co-Simulation functions and
 *
 * 1. at the first fmi2Instantiate finds a Python (in this order):
 *    - the Python already running in the process (fmpy, libcosimpy);
 *    - the runtime the FMU carries, resources/python/ (a standalone FMU, built with
 *      build_fmu.py --standalone): resources/python/runtime.txt names its shared
 *      libpython and its library folder, both relative to resources/python/;
 *    - the Python of this machine: $TOWCABLE_PYTHON, else python3 on the PATH, asked
 *      for its shared libpython and sys.path;
 *    loads that libpython with RTLD_GLOBAL, starts it as an isolated interpreter (its
 *    module path set explicitly, no signal handlers) and releases the GIL, as
 *    pythonfmu's own initialisation does; the interpreter is never finalised (numpy and
 *    numba cannot be re-initialised in a process; later FMUs reuse it);
 * 2. loads pythonfmu's library and forwards every FMI call to it;
 * 3. wraps each instance: pythonfmu gets logging always on and a logger of ours, which
 *    passes to the host's logger every message of status fmi2Discard or worse, and the
 *    others only as the host asked (loggingOn, fmi2SetDebugLogging categories); each
 *    call returns the most severe of pythonfmu's status and the statuses logged during
 *    the call, so an error the model reports is an fmi2Error the host sees;
 * 4. enforces the FMI 2.0 Co-Simulation state machine (state_machine.c: the rules;
 *    model_table.c: the variables of modelDescription.xml) before pythonfmu sees a call:
 *    a call not allowed in the instance's state, a set the variable's causality or
 *    variability forbids, an unknown value reference, a NULL array, a non-finite Real
 *    parameter, a component or FMU state that is not a live one of this FMU (pointers
 *    are looked up in registries, never followed first) are refused with fmi2Error and a
 *    message naming the call, the variable and the state, and change nothing;
 * 5. serialises FMU states in an envelope (state_bytes.c: FMU name, GUID, the state
 *    machine's state, CRC-32) and refuses bytes that fail it, so that pythonfmu only
 *    ever deserialises bytes it wrote;
 * 6. shares each instance's values with its slave (shared_values.h): once the slave has
 *    handed them over (initialised, step mode), gets of Real, Integer and Boolean
 *    variables and sets of Real inputs are served here without Python, and a slave with
 *    a compiled step (all three; TowCable's is its Simulation's) steps without Python too, and so do
 *    gets of String parameters the slave has given once since the last call that went to
 *    it (keep_strings); anything else, and a compiled call that declines (a non-finite
 *    input, a time that does not follow), goes to pythonfmu, whose slave takes the values
 *    back first. The buffer's
 *    address reaches only the slave being created: towcable_shared_values() answers
 *    during fmi2Instantiate and fmi2Reset on their thread, no FMI call carries it.
 *
 * pythonfmu 0.7 answers a Python exception with fmi2Fatal after releasing the slave's
 * Python objects while keeping pointers to them (PySlaveInstance::handle_py_exception);
 * each later exception releases them again, and the next call uses freed memory (the
 * segmentation fault of issue 37: two failed deserialisations, then fmi2DoStep). The
 * slaves never let an exception reach pythonfmu (towcable_fmu/fmi/slave.py) and this
 * layer keeps bad input from them; should pythonfmu still return fmi2Fatal, the instance
 * is marked broken: every later call is refused and fmi2FreeInstance leaves pythonfmu's
 * component allocated rather than release its objects a second time.
 *
 * A failure to start (no Python, a missing file) or arguments that do not fit (another
 * GUID, Model Exchange, NULL names) make fmi2Instantiate log the reason through the
 * host's logger with status fmi2Error and return NULL.
 */
#include <Python.h>

#include <dirent.h>
#include <dlfcn.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "fmi2Functions.h"
#include "model_table.h"
#include "shared_values.h"
#include "state_bytes.h"
#include "state_machine.h"

#define REAL_LIBRARY "libpythonfmu-export.so"
#define RUNTIME_DIR "resources/python"
#define RUNTIME_FILE RUNTIME_DIR "/runtime.txt"
#define MESSAGE_SIZE 4096

/* ------------------------------------------------------------------------------------ */
/* pythonfmu's functions                                                                 */

typedef struct {
    fmi2SetDebugLoggingTYPE *SetDebugLogging;
    fmi2InstantiateTYPE *Instantiate;
    fmi2FreeInstanceTYPE *FreeInstance;
    fmi2SetupExperimentTYPE *SetupExperiment;
    fmi2EnterInitializationModeTYPE *EnterInitializationMode;
    fmi2ExitInitializationModeTYPE *ExitInitializationMode;
    fmi2TerminateTYPE *Terminate;
    fmi2ResetTYPE *Reset;
    fmi2GetRealTYPE *GetReal;
    fmi2GetIntegerTYPE *GetInteger;
    fmi2GetBooleanTYPE *GetBoolean;
    fmi2GetStringTYPE *GetString;
    fmi2SetRealTYPE *SetReal;
    fmi2SetIntegerTYPE *SetInteger;
    fmi2SetBooleanTYPE *SetBoolean;
    fmi2SetStringTYPE *SetString;
    fmi2GetFMUstateTYPE *GetFMUstate;
    fmi2SetFMUstateTYPE *SetFMUstate;
    fmi2FreeFMUstateTYPE *FreeFMUstate;
    fmi2SerializedFMUstateSizeTYPE *SerializedFMUstateSize;
    fmi2SerializeFMUstateTYPE *SerializeFMUstate;
    fmi2DeSerializeFMUstateTYPE *DeSerializeFMUstate;
    fmi2GetDirectionalDerivativeTYPE *GetDirectionalDerivative;
    fmi2SetRealInputDerivativesTYPE *SetRealInputDerivatives;
    fmi2GetRealOutputDerivativesTYPE *GetRealOutputDerivatives;
    fmi2DoStepTYPE *DoStep;
    fmi2CancelStepTYPE *CancelStep;
    fmi2GetStatusTYPE *GetStatus;
    fmi2GetRealStatusTYPE *GetRealStatus;
    fmi2GetIntegerStatusTYPE *GetIntegerStatus;
    fmi2GetBooleanStatusTYPE *GetBooleanStatus;
    fmi2GetStringStatusTYPE *GetStringStatus;
} RealFunctions;

#define SYMBOL(name) {"fmi2" #name, offsetof(RealFunctions, name)}
static const struct {
    const char *name;
    size_t offset;
} SYMBOLS[] = {
    SYMBOL(SetDebugLogging), SYMBOL(Instantiate), SYMBOL(FreeInstance), SYMBOL(SetupExperiment),
    SYMBOL(EnterInitializationMode), SYMBOL(ExitInitializationMode), SYMBOL(Terminate),
    SYMBOL(Reset), SYMBOL(GetReal), SYMBOL(GetInteger), SYMBOL(GetBoolean), SYMBOL(GetString),
    SYMBOL(SetReal), SYMBOL(SetInteger), SYMBOL(SetBoolean), SYMBOL(SetString),
    SYMBOL(GetFMUstate), SYMBOL(SetFMUstate), SYMBOL(FreeFMUstate),
    SYMBOL(SerializedFMUstateSize), SYMBOL(SerializeFMUstate), SYMBOL(DeSerializeFMUstate),
    SYMBOL(GetDirectionalDerivative), SYMBOL(SetRealInputDerivatives),
    SYMBOL(GetRealOutputDerivatives), SYMBOL(DoStep), SYMBOL(CancelStep), SYMBOL(GetStatus),
    SYMBOL(GetRealStatus), SYMBOL(GetIntegerStatus), SYMBOL(GetBooleanStatus),
    SYMBOL(GetStringStatus),
};
#undef SYMBOL

static RealFunctions real;
static void *real_handle = NULL;
static ModelTable model;              /* this FMU's variables, read with pythonfmu's library */
static char model_identifier[256];    /* the name of this library without ".so" */
static pthread_mutex_t load_lock = PTHREAD_MUTEX_INITIALIZER;

/* ------------------------------------------------------------------------------------ */
/* small helpers                                                                        */

static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* Split text into its non-empty lines (in place); the number of lines. */
static size_t split_lines(char *text, char **lines, size_t max)
{
    size_t n = 0;
    for (char *line = strtok(text, "\r\n"); line && n < max; line = strtok(NULL, "\r\n")) lines[n++] = line;
    return n;
}

/* ------------------------------------------------------------------------------------ */
/* starting Python                                                                      */

static int python_running(void)
{
    int (*initialized)(void) = (int (*)(void))dlsym(RTLD_DEFAULT, "Py_IsInitialized");
    return initialized != NULL && initialized();
}

/* Where a Python is: its shared library, its home (or NULL), the program name to give it
   and the module search path. */
#define MAX_PATHS 64
typedef struct {
    char library[PATH_MAX];
    char home[PATH_MAX];
    char program[PATH_MAX];
    char *paths[MAX_PATHS];
    size_t npaths;
    char *storage; /* owns the path strings */
} PythonPlace;

typedef struct {
    __typeof__(Py_IsInitialized) *IsInitialized;
    __typeof__(PyConfig_InitIsolatedConfig) *InitIsolatedConfig;
    __typeof__(PyConfig_SetBytesString) *SetBytesString;
    __typeof__(PyWideStringList_Append) *ListAppend;
    __typeof__(Py_DecodeLocale) *DecodeLocale;
    __typeof__(PyMem_RawFree) *RawFree;
    __typeof__(Py_InitializeFromConfig) *InitializeFromConfig;
    __typeof__(PyConfig_Clear) *ConfigClear;
    __typeof__(PyStatus_Exception) *StatusException;
    __typeof__(PyEval_SaveThread) *SaveThread;
    __typeof__(Py_GetVersion) *GetVersion;
} PythonApi;

/* The standalone runtime in resources/python (0 if the FMU carries none). */
static int carried_python(const char *root, PythonPlace *place, char *err, size_t n)
{
    char path[PATH_MAX + 64];
    snprintf(path, sizeof path, "%s/" RUNTIME_FILE, root);
    char *text = read_text_file(path);
    if (!text) return 0;
    char *lines[2];
    size_t count = split_lines(text, lines, 2);
    int ok = count == 2;
    if (ok) {
        snprintf(place->home, sizeof place->home, "%s/" RUNTIME_DIR, root);
        snprintf(place->library, sizeof place->library, "%s/%s", place->home, lines[0]);
        snprintf(place->program, sizeof place->program, "%s/bin/python3", place->home);
        /* the library folder, its lib-dynload and site-packages */
        size_t size = 3 * (strlen(place->home) + strlen(lines[1]) + 32);
        place->storage = malloc(size);
        ok = place->storage != NULL;
        if (ok) {
            char *p = place->storage;
            const char *suffix[] = {"", "/lib-dynload", "/site-packages"};
            for (int i = 0; i < 3; i++) {
                place->paths[place->npaths++] = p;
                p += sprintf(p, "%s/%s%s", place->home, lines[1], suffix[i]) + 1;
            }
        }
    }
    if (!ok) snprintf(err, n, "%s is malformed (two lines: the shared libpython and the library folder)", path);
    free(text);
    return ok ? 1 : -1;
}

/* The Python of this machine: $TOWCABLE_PYTHON or python3 on the PATH, asked for its
   shared library, executable and sys.path (one per line). */
static int machine_python(PythonPlace *place, char *err, size_t n)
{
    const char *python = getenv("TOWCABLE_PYTHON");
    if (!python || !*python) python = "python3";
    static const char script[] =
        "import os, sys, sysconfig; v = sysconfig.get_config_var; "
        "libs = [os.path.join(v('LIBDIR') or '', x) for x in (v('INSTSONAME'), v('LDLIBRARY')) if x and '.so' in x]; "
        "libs = [x for x in libs if os.path.isfile(x)]; "
        "print(libs[0] if libs else '-'); print(sys.executable); "
        "[print(p) for p in sys.path if p and os.path.exists(p)]";
    char command[PATH_MAX + sizeof script + 64];
    if (strchr(python, '\'')) {
        snprintf(err, n, "$TOWCABLE_PYTHON (%s) must not contain a quote", python);
        return 0;
    }
    snprintf(command, sizeof command, "'%s' -c \"%s\" 2>/dev/null", python, script);
    FILE *pipe = popen(command, "r");
    size_t size = 0, cap = 0;
    char *text = NULL;
    if (pipe) {
        char buffer[4096];
        size_t got;
        while ((got = fread(buffer, 1, sizeof buffer, pipe)) > 0) {
            if (size + got + 1 > cap) {
                cap = 2 * (size + got + 1);
                char *grown = realloc(text, cap);
                if (!grown) break;
                text = grown;
            }
            memcpy(text + size, buffer, got);
            size += got;
        }
        pclose(pipe);
    }
    if (text) text[size] = '\0';
    char *lines[MAX_PATHS + 2];
    size_t count = text ? split_lines(text, lines, MAX_PATHS + 2) : 0;
    if (count < 3 || strcmp(lines[0], "-") == 0) {
        snprintf(err, n, "this FMU needs a Python: it runs inside Python hosts (fmpy, libcosimpy), or in other "
                 "hosts with a Python 3 that has a shared libpython and the packages of the FMU's "
                 "resources/requirements.txt, found as $TOWCABLE_PYTHON or python3 on the PATH (%s: %s); "
                 "for hosts without Python use the standalone FMU (python build_fmu.py --standalone)",
                 python, count == 0 ? "not found or failed" : "it has no shared libpython");
        free(text);
        return 0;
    }
    snprintf(place->library, sizeof place->library, "%s", lines[0]);
    snprintf(place->program, sizeof place->program, "%s", lines[1]);
    place->home[0] = '\0';
    place->storage = text;
    for (size_t i = 2; i < count; i++) place->paths[place->npaths++] = lines[i];
    return 1;
}

/* Initialise the interpreter of place (isolated, its module path) and release the GIL. */
static int initialize_python(const PythonApi *py, const PythonPlace *place, char *err, size_t n)
{
    PyConfig config;
    py->InitIsolatedConfig(&config);
    PyStatus status = py->SetBytesString(&config, &config.program_name, place->program);
    if (!py->StatusException(status) && place->home[0])
        status = py->SetBytesString(&config, &config.home, place->home);
    config.module_search_paths_set = 1;
    config.install_signal_handlers = 0;
    for (size_t i = 0; i < place->npaths && !py->StatusException(status); i++) {
        wchar_t *wide = py->DecodeLocale(place->paths[i], NULL);
        if (!wide) {
            snprintf(err, n, "cannot decode the module path %s", place->paths[i]);
            py->ConfigClear(&config);
            return 0;
        }
        status = py->ListAppend(&config.module_search_paths, wide);
        py->RawFree(wide);
    }
    if (!py->StatusException(status)) status = py->InitializeFromConfig(&config);
    py->ConfigClear(&config);
    if (py->StatusException(status)) {
        snprintf(err, n, "Python (%s) failed to start: %s%s%s", place->library,
                 status.func ? status.func : "", status.func ? ": " : "",
                 status.err_msg ? status.err_msg : "unknown error");
        return 0;
    }
    py->SaveThread();
    return 1;
}

/* Load and start the Python of place. */
static int start_place(const PythonPlace *place, char *err, size_t n)
{
    if (!exists(place->library)) {
        snprintf(err, n, "the Python library %s does not exist", place->library);
        return 0;
    }
    void *lib = dlopen(place->library, RTLD_NOW | RTLD_GLOBAL); /* kept: Python stays loaded */
    PythonApi py;
    void *symbols[] = {
        dlsym(lib, "Py_IsInitialized"), dlsym(lib, "PyConfig_InitIsolatedConfig"),
        dlsym(lib, "PyConfig_SetBytesString"), dlsym(lib, "PyWideStringList_Append"),
        dlsym(lib, "Py_DecodeLocale"), dlsym(lib, "PyMem_RawFree"),
        dlsym(lib, "Py_InitializeFromConfig"), dlsym(lib, "PyConfig_Clear"),
        dlsym(lib, "PyStatus_Exception"), dlsym(lib, "PyEval_SaveThread"), dlsym(lib, "Py_GetVersion"),
    };
    int ok = lib != NULL;
    for (size_t i = 0; ok && i < sizeof symbols / sizeof *symbols; i++) ok = symbols[i] != NULL;
    if (!ok) {
        snprintf(err, n, "cannot load the Python library %s: %s", place->library,
                 lib ? "it lacks the PyConfig API (Python >= 3.8 needed)" : dlerror());
        return 0;
    }
    _Static_assert(sizeof py == sizeof symbols, "one symbol per PythonApi member");
    memcpy(&py, symbols, sizeof py);
    /* PyConfig's layout is that of the headers this layer was compiled with */
    char expected[16];
    snprintf(expected, sizeof expected, "%d.%d.", PY_MAJOR_VERSION, PY_MINOR_VERSION);
    if (strncmp(py.GetVersion(), expected, strlen(expected)) != 0) {
        snprintf(err, n, "the Python library %s is version %.12s, but this FMU was built for Python %d.%d "
                 "(set TOWCABLE_PYTHON to a Python %d.%d, or rebuild the FMU with it)", place->library,
                 py.GetVersion(), PY_MAJOR_VERSION, PY_MINOR_VERSION, PY_MAJOR_VERSION, PY_MINOR_VERSION);
        return 0;
    }
    return py.IsInitialized() || initialize_python(&py, place, err, n);
}

static int start_python(const char *root, char *err, size_t n)
{
    PythonPlace place;
    memset(&place, 0, sizeof place);
    int found = carried_python(root, &place, err, n);
    if (found == 0) found = machine_python(&place, err, n);
    int ok = found == 1 && start_place(&place, err, n);
    free(place.storage);
    return ok;
}

/* ------------------------------------------------------------------------------------ */
/* loading pythonfmu's library                                                          */

/* The folder of this library and the FMU's root folder (two levels up); the library's
   name without ".so" is the modelIdentifier. */
static int own_folders(char *dir, char *root, size_t n)
{
    Dl_info info;
    if (!dladdr((void *)&own_folders, &info) || !info.dli_fname || !realpath(info.dli_fname, dir))
        return 0;
    char *slash = strrchr(dir, '/');
    if (!slash) return 0;
    *slash = '\0';
    snprintf(model_identifier, sizeof model_identifier, "%s", slash + 1);
    char *suffix = strstr(model_identifier, ".so");
    if (suffix) *suffix = '\0';
    snprintf(root, n, "%s/../..", dir);
    return 1;
}

/* Let pythonfmu release its Python state, then unload its library. pythonfmu does the
   former in a destructor function, which at process exit runs after its static objects
   were destroyed (an invalid read of freed memory). Exit handlers run in reverse order of
   registration, also at dlclose of this library: registered once pythonfmu's library is
   loaded, this one runs before pythonfmu's static destructors. */
static void release_real(void)
{
    void (*finalize)(void) = (void (*)(void))dlsym(real_handle, "finalizePythonInterpreter");
    if (finalize) finalize();
    dlclose(real_handle);
    real_handle = NULL;
    memset(&real, 0, sizeof real);
    free(model.variables);
    free(model.index);
    memset(&model, 0, sizeof model);
}

static int load_real(char *err, size_t n)
{
    char dir[PATH_MAX], root[PATH_MAX + 8], path[PATH_MAX + 32];
    if (!own_folders(dir, root, sizeof root)) {
        snprintf(err, n, "cannot find the folder of the FMU's binary");
        return 0;
    }
    if (!model_table_read(root, &model, err, n)) return 0;
    for (size_t i = 0; i < model.count; i++) { /* the set rules per variable, once */
        Variable *v = &model.variables[i];
        char why[8];
        for (Phase p = 0; p < PHASE_COUNT; p++)
            if (set_allowed(v, p, why, sizeof why)) v->settable |= 1u << p;
        v->parameter = strcmp(v->causality, "parameter") == 0;
        v->input = strcmp(v->causality, "input") == 0;
    }
    if (!python_running() && !start_python(root, err, n)) return 0;
    snprintf(path, sizeof path, "%s/%s", dir, REAL_LIBRARY);
    void *handle = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        snprintf(err, n, "cannot load pythonfmu's library: %s", dlerror());
        return 0;
    }
    for (size_t i = 0; i < sizeof SYMBOLS / sizeof *SYMBOLS; i++) {
        void *sym = dlsym(handle, SYMBOLS[i].name);
        if (!sym) {
            snprintf(err, n, "%s lacks %s", path, SYMBOLS[i].name);
            memset(&real, 0, sizeof real);
            dlclose(handle);
            return 0;
        }
        memcpy((char *)&real + SYMBOLS[i].offset, &sym, sizeof sym);
    }
    real_handle = handle;
    atexit(release_real);
    return 1;
}


/* ------------------------------------------------------------------------------------ */
/* instances and FMU states: the host's logger behind ours, the worst status of a call, */
/* the phase of the state machine; registries of the live ones                          */

typedef struct Instance {
    struct Instance *next;           /* the live instances of this FMU */
    fmi2Component real;              /* pythonfmu's component */
    char *name;
    fmi2CallbackFunctions host;      /* the host's callbacks */
    fmi2CallbackFunctions relay;     /* what pythonfmu gets: our logger, this instance as environment */
    int logging_on;                  /* what the host asked for */
    char **categories;               /* the host's categories; none: all */
    size_t ncategories;
    fmi2Status worst;                /* most severe status logged during the current call */
    char first_error[512];           /* the first error message logged during the current call */
    Phase phase;                     /* the state machine's state (state_machine.h) */
    char error_cause[512];           /* in the error state: the message of the call that failed */
    SharedValues *shared;            /* the values shared with the slave (shared_values.h) */
    char **strings;                  /* String parameters by value reference as the slave gave them
                                        (NULL: none kept; see keep_strings) */
    int stepped;                     /* a step succeeded: last_step_end is its end */
    fmi2Real last_step_end;          /* fmi2LastSuccessfulTime [s] */
} Instance;

/* An FMU state given to the host: pythonfmu's (a Python object) and the phase it was
   taken in; usable by every instance of this FMU until freed or its owner is freed. */
typedef struct State {
    struct State *next;              /* the live states of this FMU */
    Instance *owner;                 /* the instance that made it (frees it at the latest) */
    Phase phase;
    fmi2FMUstate real;
    unsigned char *bytes;            /* its serialisation (state_bytes.h), made at first need */
    size_t size;
} State;

static pthread_mutex_t live_lock = PTHREAD_MUTEX_INITIALIZER;
static Instance *live_instances = NULL;
static State *live_states = NULL;

/* Whether c is a live instance of this FMU (pointers from the host are compared, never
   followed, before they are found here). */
static int is_live(const void *c)
{
    pthread_mutex_lock(&live_lock);
    const Instance *i = live_instances;
    while (i && (const void *)i != c) i = i->next;
    pthread_mutex_unlock(&live_lock);
    return i != NULL;
}

static State *find_state(const void *s)
{
    pthread_mutex_lock(&live_lock);
    State *st = live_states;
    while (st && (const void *)st != s) st = st->next;
    pthread_mutex_unlock(&live_lock);
    return st;
}

/* Take st (or, with st NULL, every state of owner) out of the registry; the states taken
   out, linked. */
static State *unlink_states(const State *st, const Instance *owner)
{
    State *taken = NULL;
    pthread_mutex_lock(&live_lock);
    for (State **p = &live_states; *p;) {
        State *cur = *p;
        if (cur == st || (!st && cur->owner == owner)) {
            *p = cur->next;
            cur->next = taken;
            taken = cur;
        } else {
            p = &cur->next;
        }
    }
    pthread_mutex_unlock(&live_lock);
    return taken;
}

/* Pass text to a logger as the standard wants it: a printf format, '%' doubled. */
static void send_text(const fmi2CallbackFunctions *to, fmi2String instance, fmi2Status status,
                      fmi2String category, const char *text)
{
    char escaped[2 * MESSAGE_SIZE];
    size_t j = 0;
    for (size_t i = 0; text[i] && j + 2 < sizeof escaped; i++) {
        if (text[i] == '%') escaped[j++] = '%';
        escaped[j++] = text[i];
    }
    escaped[j] = '\0';
    if (to && to->logger)
        to->logger(to->componentEnvironment, instance, status, category, escaped);
    else
        fprintf(stderr, "%s: %s\n", instance ? instance : "FMU", text);
}

static int category_enabled(const Instance *inst, const char *category)
{
    if (inst->ncategories == 0) return 1;
    for (size_t i = 0; i < inst->ncategories; i++)
        if (strcmp(inst->categories[i], category) == 0 || strcmp(inst->categories[i], "logAll") == 0) return 1;
    return 0;
}

/* pythonfmu's messages are plain text (it passes no format arguments). */
static void relay_logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                         fmi2String category, fmi2String message, ...)
{
    Instance *inst = (Instance *)env;
    if (status > inst->worst && status != fmi2Pending) inst->worst = status;
    if (status >= fmi2Error && !inst->first_error[0] && message)
        snprintf(inst->first_error, sizeof inst->first_error, "%s", message);
    const char *cat = category ? category : "";
    if (status >= fmi2Discard || (inst->logging_on && category_enabled(inst, cat)))
        send_text(&inst->host, instance, status, cat, message ? message : "");
}

static void clear_categories(Instance *inst)
{
    for (size_t i = 0; i < inst->ncategories; i++) free(inst->categories[i]);
    free(inst->categories);
    inst->categories = NULL;
    inst->ncategories = 0;
}

/* Refuse a call: fmi2Error with a message naming the call, the reason and the state. */
static fmi2Status refuse(Instance *inst, const char *call, const char *format, ...)
{
    char text[MESSAGE_SIZE];
    int k = snprintf(text, sizeof text, "%s: %s: ", inst->name, call);
    va_list args;
    va_start(args, format);
    if (k > 0 && (size_t)k < sizeof text) k += vsnprintf(text + k, sizeof text - (size_t)k, format, args);
    va_end(args);
    if (k > 0 && (size_t)k < sizeof text)
        snprintf(text + k, sizeof text - (size_t)k, " (state: %s%s%s)", phase_name(inst->phase),
                 inst->phase == PHASE_ERROR && inst->error_cause[0] ? ", entered on: " : "",
                 inst->phase == PHASE_ERROR ? inst->error_cause : "");
    send_text(&inst->host, inst->name, fmi2Error, "logStatusError", text);
    return fmi2Error;
}

/* Whether the call may go on: c is a live instance and the state machine allows it;
   else *status is the call's fmi2Error. Clears the call's worst logged status. */
static int admit(Instance *inst, Call call, const char *name, fmi2Status *status)
{
    *status = fmi2Error;
    if (!is_live(inst)) {
        fprintf(stderr, "%s: %s: the component %p is not a live instance of this FMU (NULL, freed or foreign); "
                "the call is refused with fmi2Error\n", model_identifier, name, (void *)inst);
        return 0;
    }
    if (!call_allowed(call, inst->phase)) {
        refuse(inst, name, "the call is not allowed in this state");
        return 0;
    }
    inst->worst = fmi2OK;
    inst->first_error[0] = '\0';
    return 1;
}

/* The status of a forwarded call: pythonfmu's, or a more severe one logged during it;
   the phase moves as the state machine says. */
static fmi2Status finish(Instance *inst, Call call, fmi2Status status)
{
    if (status != fmi2Pending && status < inst->worst) status = inst->worst;
    Phase before = inst->phase;
    inst->phase = phase_after(call, before, status);
    if (inst->phase == PHASE_ERROR && before != PHASE_ERROR)
        snprintf(inst->error_cause, sizeof inst->error_cause, "%s", inst->first_error);
    return status;
}

#define ADMIT(call, name)                                               \
    Instance *inst = (Instance *)c;                                     \
    fmi2Status refused;                                                 \
    if (!admit(inst, call, name, &refused)) return refused

/* ------------------------------------------------------------------------------------ */
/* values shared with the slave                                                         */

/* The instance whose slave pythonfmu is creating on this thread (fmi2Instantiate,
   fmi2Reset): the only one towcable_shared_values() answers for. */
static __thread Instance *attaching = NULL;

SharedValues *towcable_shared_values(void) { return attaching ? attaching->shared : NULL; }

static SharedValues *new_shared_values(void)
{
    SharedValues *sh = calloc(1, sizeof *sh + model.index_size * sizeof(double));
    if (sh) {
        sh->version = SHARED_VALUES_VERSION;
        sh->timer_vr = -1;
        sh->count = model.index_size;
    }
    return sh;
}

static double seconds_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Add the wall time since start [s] to the slave's model time output. */
static void add_model_time(SharedValues *sh, double start)
{
    if (sh->timer_vr >= 0 && (uint64_t)sh->timer_vr < sh->count) sh->values[sh->timer_vr] += seconds_now() - start;
}

/* The slave's compiled outputs of the inputs set since (feedthrough); 0 if it declined. */
static int update_outputs(SharedValues *sh)
{
    if (!sh->outputs_stale || !sh->outputs) return 1;
    double start = seconds_now();
    if (sh->outputs(sh->values, sh->model) != 0) return 0;
    add_model_time(sh, start);
    sh->outputs_stale = 0;
    return 1;
}

/* A get served from the shared values (1), or 0: the slave answers it. */
#define SERVE_GET(ctype)                                                          \
    do {                                                                          \
        SharedValues *sh = inst->shared;                                          \
        if (sh && sh->served && update_outputs(sh)) {                             \
            for (size_t i = 0; i < n; i++) v[i] = (ctype)sh->values[vr[i]];       \
            return fmi2OK;                                                        \
        }                                                                         \
    } while (0)

/* String parameters change only in a call that enters the slave (fmi2SetString, a restored
   state, a reset, a step or mode change it makes): the values it last gave are kept to answer
   fmi2GetString while the values are served (a host that reads every variable at every step,
   as libcosim's observers do, would otherwise enter Python at every step), and forgotten at
   every call but a get that goes to the slave. */
static void forget_strings(Instance *inst)
{
    if (!inst->strings) return;
    for (size_t i = 0; i < model.index_size; i++) free(inst->strings[i]);
    free(inst->strings);
    inst->strings = NULL;
}

static void keep_strings(Instance *inst, const fmi2ValueReference vr[], size_t n, const fmi2String v[])
{
    if (!inst->shared || !inst->shared->served) return;
    if (!inst->strings) inst->strings = calloc(model.index_size, sizeof *inst->strings);
    for (size_t i = 0; inst->strings && i < n; i++) {
        const Variable *var = model_table_find(&model, TYPE_STRING, vr[i]);
        if (var && var->parameter && v[i] && vr[i] < model.index_size && !inst->strings[vr[i]])
            inst->strings[vr[i]] = strdup(v[i]);
    }
}

/* A get of String parameters answered from those kept (1), or 0: the slave answers it. */
static int serve_get_string(Instance *inst, const fmi2ValueReference vr[], size_t n, fmi2String v[])
{
    if (!inst->strings || !inst->shared || !inst->shared->served) return 0;
    for (size_t i = 0; i < n; i++)
        if (vr[i] >= model.index_size || !inst->strings[vr[i]]) return 0;
    for (size_t i = 0; i < n; i++) v[i] = inst->strings[vr[i]];
    return 1;
}

/* Sets of Real inputs kept in the shared values (1), or 0: the slave takes them. */
static int serve_set_real(Instance *inst, const fmi2ValueReference vr[], size_t n, const fmi2Real v[])
{
    SharedValues *sh = inst->shared;
    if (!sh || !sh->served) return 0;
    for (size_t i = 0; i < n; i++) {
        const Variable *var = model_table_find(&model, TYPE_REAL, vr[i]);
        if (!var || !var->input) return 0;
    }
    for (size_t i = 0; i < n; i++) sh->values[vr[i]] = v[i];
    sh->inputs_set = 1;
    sh->outputs_stale = 1;
    return 1;
}

/* A step made by the slave's compiled step (1), or 0: the slave makes (or refuses) it. */
static int compiled_step(Instance *inst, fmi2Real t, fmi2Real h)
{
    SharedValues *sh = inst->shared;
    if (!sh || !sh->served || !sh->step || !isfinite(t) || !isfinite(h) || !(h > 0.0)
        || fabs(t - sh->time) > 1e-9 * fmax(1.0, fabs(t)))
        return 0;
    if (!update_outputs(sh)) return 0; /* a feedthrough slave steps from the outputs of its inputs */
    double start = seconds_now();
    if (sh->step(sh->values, sh->model, t, h) != 0) return 0;
    add_model_time(sh, start);
    sh->time = t + h;
    sh->outputs_stale = 0;
    sh->compiled_steps++;
    return 1;
}

/* The variables of a get or set call exist with this type and, for a set, may be set in
   the instance's phase; a set Real parameter is finite. */
static fmi2Status check_variables(Instance *inst, const char *call, VariableType type,
                                  const fmi2ValueReference vr[], size_t n, const void *values, int setting)
{
    if (n > 0 && (!vr || !values)) return refuse(inst, call, "NULL value reference or value array for %zu values", n);
    for (size_t i = 0; i < n; i++) {
        const Variable *v = model_table_find(&model, type, vr[i]);
        char why[512];
        if (!v)
            return refuse(inst, call, "value reference %u is not a %s variable of %s", (unsigned)vr[i],
                          type_name(type), model_identifier);
        if (!setting) continue;
        if (!(v->settable & (1u << inst->phase)) && !set_allowed(v, inst->phase, why, sizeof why))
            return refuse(inst, call, "variable '%s' (value reference %u): %s", v->name, (unsigned)vr[i], why);
        if (type == TYPE_REAL && v->parameter && !isfinite(((const fmi2Real *)values)[i]))
            return refuse(inst, call, "parameter '%s' = %g is not a finite number; the value is not set", v->name,
                          ((const fmi2Real *)values)[i]);
        if (type == TYPE_STRING && !((const fmi2String *)values)[i])
            return refuse(inst, call, "variable '%s': NULL string", v->name);
    }
    return fmi2OK;
}

/* ------------------------------------------------------------------------------------ */
/* FMI 2.0 functions                                                                    */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

/* Why the arguments of fmi2Instantiate cannot be used (NULL if they can). */
static const char *bad_instantiation(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                                     fmi2String fmuResourceLocation, char *why, size_t n)
{
    if (!instanceName || !fmuResourceLocation) return "instanceName and fmuResourceLocation must not be NULL";
    if (fmuType != fmi2CoSimulation) return "this FMU is for Co-Simulation only (fmuType fmi2CoSimulation)";
    if (!fmuGUID || strcmp(fmuGUID, model.guid) != 0) {
        snprintf(why, n, "the GUID %.100s is not this FMU's (%s): the host read another modelDescription.xml",
                 fmuGUID ? fmuGUID : "(NULL)", model.guid);
        return why;
    }
    return NULL;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    char err[MESSAGE_SIZE] = "";
    pthread_mutex_lock(&load_lock);
    int ok = real_handle != NULL || load_real(err, sizeof err);
    pthread_mutex_unlock(&load_lock);
    const char *bad = ok ? bad_instantiation(instanceName, fmuType, fmuGUID, fmuResourceLocation, err, sizeof err)
                         : err;
    Instance *inst = bad ? NULL : calloc(1, sizeof *inst);
    if (inst) inst->name = strdup(instanceName);
    if (!bad && (!inst || !inst->name)) bad = "out of memory";
    if (bad) {
        send_text(functions, instanceName, fmi2Error, "logStatusError", bad);
        if (inst) free(inst);
        return NULL;
    }
    if (functions) inst->host = *functions;
    inst->relay = inst->host;
    inst->relay.logger = relay_logger;
    inst->relay.componentEnvironment = inst;
    inst->logging_on = loggingOn;
    inst->phase = PHASE_INSTANTIATED;
    inst->shared = new_shared_values();
    attaching = inst;
    inst->real = real.Instantiate(instanceName, fmuType, fmuGUID, fmuResourceLocation, &inst->relay, visible,
                                  fmi2True);
    attaching = NULL;
    if (!inst->real) {
        if (inst->worst < fmi2Error)
            send_text(functions, instanceName, fmi2Error, "logStatusError",
                      "pythonfmu could not instantiate the model (no message)");
        free(inst->shared);
        free(inst->name);
        free(inst);
        return NULL;
    }
    pthread_mutex_lock(&live_lock);
    inst->next = live_instances;
    live_instances = inst;
    pthread_mutex_unlock(&live_lock);
    return inst;
}

static void free_state(Instance *by, State *st)
{
    if (st->real) real.FreeFMUstate(by->real, &st->real);
    free(st->bytes);
    free(st);
}

/* After fmi2Fatal pythonfmu has released its Python objects but keeps pointers to them
   (PySlaveInstance::handle_py_exception): freeing its component would release them again.
   A broken instance's component is therefore left allocated (a few hundred bytes). */
void fmi2FreeInstance(fmi2Component c)
{
    Instance *inst = (Instance *)c;
    pthread_mutex_lock(&live_lock);
    Instance **p = &live_instances;
    while (*p && *p != inst) p = &(*p)->next;
    int live = *p != NULL;
    if (live) *p = inst->next;
    pthread_mutex_unlock(&live_lock);
    if (!live) {
        if (inst)
            fprintf(stderr, "%s: fmi2FreeInstance: the component %p is not a live instance of this FMU (freed "
                    "twice or foreign); ignored\n", model_identifier, (void *)inst);
        return;
    }
    for (State *st = unlink_states(NULL, inst), *next; st; st = next) {
        next = st->next;
        free_state(inst, st);
    }
    if (inst->shared) inst->shared->served = 0;
    if (inst->phase != PHASE_BROKEN) real.FreeInstance(inst->real);
    forget_strings(inst);
    clear_categories(inst);
    free(inst->shared);
    free(inst->name);
    free(inst);
}

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String cat[])
{
    ADMIT(CALL_SET_DEBUG_LOGGING, "fmi2SetDebugLogging");
    if (on && n > 0 && !cat) return refuse(inst, "fmi2SetDebugLogging", "NULL categories array for %zu categories", n);
    clear_categories(inst);
    inst->logging_on = on;
    if (on && n > 0) {
        inst->categories = calloc(n, sizeof *inst->categories);
        for (size_t i = 0; inst->categories && i < n; i++) {
            inst->categories[i] = strdup(cat[i] ? cat[i] : "");
            inst->ncategories = i + 1;
        }
    }
    return fmi2OK;
}

/* Admit the call, forward it to pythonfmu with its component, finish it. */
#define FORWARD(call, name, ...)                                        \
    do {                                                                \
        ADMIT(CALL_##call, "fmi2" #name);                               \
        forget_strings(inst);                                           \
        return finish(inst, CALL_##call, real.name(inst->real, ##__VA_ARGS__)); \
    } while (0)

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDefined, fmi2Real tol, fmi2Real start,
                               fmi2Boolean stopDefined, fmi2Real stop)
{ FORWARD(SETUP_EXPERIMENT, SetupExperiment, tolDefined, tol, start, stopDefined, stop); }

fmi2Status fmi2EnterInitializationMode(fmi2Component c) { FORWARD(ENTER_INITIALIZATION, EnterInitializationMode); }
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { FORWARD(EXIT_INITIALIZATION, ExitInitializationMode); }
fmi2Status fmi2Terminate(fmi2Component c) { FORWARD(TERMINATE, Terminate); }

/* pythonfmu makes a new slave: it takes the shared values afresh */
fmi2Status fmi2Reset(fmi2Component c)
{
    ADMIT(CALL_RESET, "fmi2Reset");
    forget_strings(inst);
    if (inst->shared) inst->shared->served = 0;
    inst->stepped = 0;
    attaching = inst;
    fmi2Status status = real.Reset(inst->real);
    attaching = NULL;
    return finish(inst, CALL_RESET, status);
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior)
{
    ADMIT(CALL_DO_STEP, "fmi2DoStep");
    fmi2Status status;
    if (compiled_step(inst, t, h)) {
        status = fmi2OK;
    } else {
        forget_strings(inst);
        status = real.DoStep(inst->real, t, h, noSetPrior);
    }
    status = finish(inst, CALL_DO_STEP, status);
    if (status <= fmi2Warning) {
        inst->stepped = 1;
        inst->last_step_end = t + h;
    }
    return status;
}

/* A set call: admitted, its variables checked, forwarded. */
#define ACCESS(call, name, type, setting)                                                       \
    do {                                                                                        \
        ADMIT(call, "fmi2" #name);                                                              \
        fmi2Status checked = check_variables(inst, "fmi2" #name, type, vr, n, v, setting);      \
        if (checked != fmi2OK || n == 0) return checked;                                        \
        forget_strings(inst);                                                                   \
        return finish(inst, call, real.name(inst->real, vr, n, v));                             \
    } while (0)

/* ... with a first try to serve it from the shared values (an expression that returns). */
#define ACCESS_SERVED(call, name, type, setting, serve)                                         \
    do {                                                                                        \
        ADMIT(call, "fmi2" #name);                                                              \
        fmi2Status checked = check_variables(inst, "fmi2" #name, type, vr, n, v, setting);      \
        if (checked != fmi2OK || n == 0) return checked;                                        \
        serve;                                                                                  \
        if (setting) forget_strings(inst);                                                      \
        return finish(inst, call, real.name(inst->real, vr, n, v));                             \
    } while (0)

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[])
{ ACCESS_SERVED(CALL_GET, GetReal, TYPE_REAL, 0, SERVE_GET(fmi2Real)); }
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[])
{ ACCESS_SERVED(CALL_GET, GetInteger, TYPE_INTEGER, 0, SERVE_GET(fmi2Integer)); }
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[])
{ ACCESS_SERVED(CALL_GET, GetBoolean, TYPE_BOOLEAN, 0, SERVE_GET(fmi2Boolean)); }
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2String v[])
{
    ADMIT(CALL_GET, "fmi2GetString");
    fmi2Status checked = check_variables(inst, "fmi2GetString", TYPE_STRING, vr, n, v, 0);
    if (checked != fmi2OK || n == 0) return checked;
    if (serve_get_string(inst, vr, n, v)) return fmi2OK;
    fmi2Status status = finish(inst, CALL_GET, real.GetString(inst->real, vr, n, v));
    if (status <= fmi2Warning) keep_strings(inst, vr, n, v);
    return status;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[])
{ ACCESS_SERVED(CALL_SET, SetReal, TYPE_REAL, 1, if (serve_set_real(inst, vr, n, v)) return fmi2OK); }
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[])
{ ACCESS(CALL_SET, SetInteger, TYPE_INTEGER, 1); }
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[])
{ ACCESS(CALL_SET, SetBoolean, TYPE_BOOLEAN, 1); }
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2String v[])
{ ACCESS(CALL_SET, SetString, TYPE_STRING, 1); }

/* ------------------------------------------------------------------------------------ */
/* FMU states                                                                           */

#define NOT_A_STATE "is not a live FMU state of %s (freed, of a freed instance, of another FMU, or never made)"

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s)
{
    ADMIT(CALL_GET_STATE, "fmi2GetFMUstate");
    if (!s) return refuse(inst, "fmi2GetFMUstate", "NULL pointer for the state");
    State *old = NULL;
    if (*s && !(old = find_state(*s)))
        return refuse(inst, "fmi2GetFMUstate", "the state %p to update " NOT_A_STATE " (pass NULL for a new one)",
                      *s, model_identifier);
    fmi2FMUstate taken = NULL;
    fmi2Status status = finish(inst, CALL_GET_STATE, real.GetFMUstate(inst->real, &taken));
    if (status >= fmi2Error || !taken) {
        if (taken && status != fmi2Fatal) real.FreeFMUstate(inst->real, &taken);
        return status >= fmi2Error ? status : refuse(inst, "fmi2GetFMUstate", "pythonfmu returned no state");
    }
    State *st = old ? old : calloc(1, sizeof *st);
    if (!st) {
        real.FreeFMUstate(inst->real, &taken);
        return refuse(inst, "fmi2GetFMUstate", "out of memory");
    }
    if (old) { /* updated in place: its previous content released */
        real.FreeFMUstate(inst->real, &old->real);
        free(old->bytes);
        old->bytes = NULL;
    }
    st->owner = inst;
    st->phase = inst->phase;
    st->real = taken;
    if (!old) {
        pthread_mutex_lock(&live_lock);
        st->next = live_states;
        live_states = st;
        pthread_mutex_unlock(&live_lock);
    }
    *s = st;
    return status;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s)
{
    ADMIT(CALL_SET_STATE, "fmi2SetFMUstate");
    State *st = find_state(s);
    if (!st) return refuse(inst, "fmi2SetFMUstate", "the state %p " NOT_A_STATE, s, model_identifier);
    forget_strings(inst);
    fmi2Status status = finish(inst, CALL_SET_STATE, real.SetFMUstate(inst->real, st->real));
    if (status < fmi2Error) inst->phase = st->phase; /* a refused state left the instance as it was */
    return status;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s)
{
    ADMIT(CALL_FREE_STATE, "fmi2FreeFMUstate");
    if (!s || !*s) return fmi2OK;
    State *st = find_state(*s);
    if (!st) return refuse(inst, "fmi2FreeFMUstate", "the state %p " NOT_A_STATE, *s, model_identifier);
    unlink_states(st, NULL);
    free_state(inst, st);
    *s = NULL;
    return fmi2OK;
}

/* The serialisation of st, made once: pythonfmu's bytes in our envelope. */
static fmi2Status serialise(Instance *inst, const char *call, State *st)
{
    if (st->bytes) return fmi2OK;
    size_t payload_size = 0;
    fmi2Status status = finish(inst, CALL_SERIALIZE, real.SerializedFMUstateSize(inst->real, st->real, &payload_size));
    if (status >= fmi2Error) return status;
    unsigned char *payload = malloc(payload_size ? payload_size : 1);
    size_t size = state_bytes_size(model_identifier, model.guid, payload_size);
    unsigned char *bytes = payload ? malloc(size) : NULL;
    if (!bytes) {
        free(payload);
        return refuse(inst, call, "out of memory for a state of %zu bytes", size);
    }
    status = finish(inst, CALL_SERIALIZE, real.SerializeFMUstate(inst->real, st->real, (fmi2Byte *)payload,
                                                                 payload_size));
    if (status < fmi2Error) {
        state_bytes_write(bytes, model_identifier, model.guid, (uint32_t)st->phase, payload, payload_size);
        st->bytes = bytes;
        st->size = size;
    } else {
        free(bytes);
    }
    free(payload);
    return status;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *size)
{
    ADMIT(CALL_SERIALIZE, "fmi2SerializedFMUstateSize");
    State *st = find_state(s);
    if (!st) return refuse(inst, "fmi2SerializedFMUstateSize", "the state %p " NOT_A_STATE, s, model_identifier);
    if (!size) return refuse(inst, "fmi2SerializedFMUstateSize", "NULL pointer for the size");
    fmi2Status status = serialise(inst, "fmi2SerializedFMUstateSize", st);
    if (status < fmi2Error) *size = st->size;
    return status;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t size)
{
    ADMIT(CALL_SERIALIZE, "fmi2SerializeFMUstate");
    State *st = find_state(s);
    if (!st) return refuse(inst, "fmi2SerializeFMUstate", "the state %p " NOT_A_STATE, s, model_identifier);
    fmi2Status status = serialise(inst, "fmi2SerializeFMUstate", st);
    if (status >= fmi2Error) return status;
    if (!b || size < st->size)
        return refuse(inst, "fmi2SerializeFMUstate", "a buffer of %zu bytes%s for a state of %zu bytes (see "
                      "fmi2SerializedFMUstateSize)", size, b ? "" : " (NULL)", st->size);
    memcpy(b, st->bytes, st->size);
    return status;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t size, fmi2FMUstate *s)
{
    ADMIT(CALL_DESERIALIZE, "fmi2DeSerializeFMUstate");
    if (!s || (!b && size > 0)) return refuse(inst, "fmi2DeSerializeFMUstate", "NULL bytes or state pointer");
    char why[512];
    uint32_t phase = 0;
    const unsigned char *payload = NULL;
    size_t payload_size = 0;
    if (!b || !state_bytes_read((const unsigned char *)b, size, model_identifier, model.guid, &phase, &payload,
                                &payload_size, why, sizeof why))
        return refuse(inst, "fmi2DeSerializeFMUstate", "refused: %s", b ? why : "no bytes");
    if (phase >= PHASE_BROKEN)
        return refuse(inst, "fmi2DeSerializeFMUstate", "refused: the state's phase %u is not a state of the "
                      "state machine", (unsigned)phase);
    State *st = calloc(1, sizeof *st);
    unsigned char *copy = st ? malloc(size) : NULL;
    if (!copy) {
        free(st);
        return refuse(inst, "fmi2DeSerializeFMUstate", "out of memory");
    }
    fmi2Status status = finish(inst, CALL_DESERIALIZE, real.DeSerializeFMUstate(inst->real, (const fmi2Byte *)payload,
                                                                                payload_size, &st->real));
    if (status >= fmi2Error || !st->real) {
        if (st->real && status != fmi2Fatal) real.FreeFMUstate(inst->real, &st->real);
        free(copy);
        free(st);
        return status >= fmi2Error ? status : refuse(inst, "fmi2DeSerializeFMUstate", "pythonfmu returned no state");
    }
    memcpy(copy, b, size);
    st->bytes = copy;
    st->size = size;
    st->owner = inst;
    st->phase = (Phase)phase;
    pthread_mutex_lock(&live_lock);
    st->next = live_states;
    live_states = st;
    pthread_mutex_unlock(&live_lock);
    *s = st;
    return status;
}

/* ------------------------------------------------------------------------------------ */
/* functions these FMUs do not provide (modelDescription: capability flags false)      */

static fmi2Status unsupported(fmi2Component c, const char *name)
{
    ADMIT(CALL_UNPROVIDED, name);
    return refuse(inst, name, "not provided by this FMU");
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference z[], size_t nz, const fmi2Real dv[],
                                        fmi2Real dz[])
{
    (void)u, (void)nu, (void)z, (void)nz, (void)dv, (void)dz;
    return unsupported(c, "fmi2GetDirectionalDerivative");
}
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                       const fmi2Integer order[], const fmi2Real v[])
{
    (void)vr, (void)n, (void)order, (void)v;
    return unsupported(c, "fmi2SetRealInputDerivatives");
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer order[], fmi2Real v[])
{
    (void)vr, (void)n, (void)order, (void)v;
    return unsupported(c, "fmi2GetRealOutputDerivatives");
}
fmi2Status fmi2CancelStep(fmi2Component c) { return unsupported(c, "fmi2CancelStep"); }

/* status inquiries: pythonfmu answers fmi2LastSuccessfulTime and fmi2Terminated */
#define STATUS(name, ...)                                               \
    do {                                                                \
        ADMIT(CALL_STATUS, "fmi2" #name);                               \
        if (!v) return refuse(inst, "fmi2" #name, "NULL value pointer"); \
        return finish(inst, CALL_STATUS, real.name(inst->real, k, v));  \
    } while (0)

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind k, fmi2Status *v) { STATUS(GetStatus); }
/* fmi2LastSuccessfulTime: the end of the last step that succeeded, also a compiled one */
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind k, fmi2Real *v)
{
    Instance *known = is_live(c) ? (Instance *)c : NULL;
    if (known && v && k == fmi2LastSuccessfulTime && known->stepped && call_allowed(CALL_STATUS, known->phase)) {
        *v = known->last_step_end;
        return fmi2OK;
    }
    STATUS(GetRealStatus);
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind k, fmi2Integer *v)
{ STATUS(GetIntegerStatus); }
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind k, fmi2Boolean *v)
{ STATUS(GetBooleanStatus); }
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind k, fmi2String *v)
{ STATUS(GetStringStatus); }
