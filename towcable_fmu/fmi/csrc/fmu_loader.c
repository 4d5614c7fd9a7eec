/*
 * towcable FMU loader: the binaries/linux64/<model>.so of the towcable FMUs.
 *
 * pythonfmu 0.7's library (kept beside this one as libpythonfmu-export.so) serves the
 * FMI calls with Python but does not link libpython: in a host without Python its
 * Python symbols cannot be resolved. This layer exports the FMI 2.0 Co-Simulation
 * functions and, at the first fmi2Instantiate,
 *
 * 1. uses the Python already in the process if there is one (fmpy, libcosimpy: the
 *    symbol Py_IsInitialized is visible and returns true);
 * 2. otherwise reads resources/python_env.json (written by towcable_fmu/fmi/native.py at
 *    build time: the interpreter, its shared library and sys.path), loads that libpython
 *    with RTLD_GLOBAL, initialises it as an isolated interpreter (PyConfig: program name
 *    = the recorded executable, so that prefix and a venv are found as by that
 *    executable; module search paths = the recorded sys.path; no signal handlers) and
 *    releases the GIL, as pythonfmu's own initialisation does (PyEval_SaveThread):
 *    pythonfmu then takes the GIL with PyGILState_Ensure in every call, from any thread;
 * 3. loads pythonfmu's library and forwards every FMI call to it; the fmi2Component is
 *    pythonfmu's own.
 *
 * The interpreter started here is never finalised: numpy and numba cannot be
 * re-initialised in a process, and FMUs loaded again later reuse it. A failure (no
 * recorded environment, a missing file) makes fmi2Instantiate log the reason through
 * the host's logger with status fmi2Error and return NULL.
 */
#include <Python.h>

#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "fmi2Functions.h"

#define REAL_LIBRARY "libpythonfmu-export.so"
#define ENV_FILE "resources/python_env.json"
#define MESSAGE_SIZE 2048

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
static pthread_mutex_t load_lock = PTHREAD_MUTEX_INITIALIZER;

/* ------------------------------------------------------------------------------------ */
/* resources/python_env.json: a flat object of strings, "sys_path" an array of strings   */

typedef struct {
    char *library;
    char *executable;
    char **paths;
    size_t npaths;
} PythonEnv;

static void env_clear(PythonEnv *env)
{
    free(env->library);
    free(env->executable);
    for (size_t i = 0; i < env->npaths; i++) free(env->paths[i]);
    free(env->paths);
    memset(env, 0, sizeof *env);
}

static const char *skip_space(const char *p)
{
    while (*p == ' ' || *p == '\n' || *p == '\r' || *p == '\t') p++;
    return p;
}

/* Append the UTF-8 encoding of a Basic Multilingual Plane code point. */
static char *put_utf8(char *out, unsigned code)
{
    if (code < 0x80) {
        *out++ = (char)code;
    } else if (code < 0x800) {
        *out++ = (char)(0xC0 | (code >> 6));
        *out++ = (char)(0x80 | (code & 0x3F));
    } else {
        *out++ = (char)(0xE0 | (code >> 12));
        *out++ = (char)(0x80 | ((code >> 6) & 0x3F));
        *out++ = (char)(0x80 | (code & 0x3F));
    }
    return out;
}

/* Parse the JSON string at *pp (at its opening quote); a new NUL-terminated buffer or
   NULL if malformed. A \uXXXX escape becomes at most 3 bytes, never more than its 6. */
static char *parse_string(const char **pp)
{
    const char *p = *pp;
    if (*p != '"') return NULL;
    const char *end = ++p;
    while (*end && *end != '"') end += (*end == '\\' && end[1]) ? 2 : 1;
    if (*end != '"') return NULL;
    char *out = malloc((size_t)(end - p) + 1), *o = out;
    if (!out) return NULL;
    while (p < end) {
        if (*p != '\\') {
            *o++ = *p++;
            continue;
        }
        char c = p[1];
        p += 2;
        switch (c) {
        case '"': case '\\': case '/': *o++ = c; break;
        case 'b': *o++ = '\b'; break;
        case 'f': *o++ = '\f'; break;
        case 'n': *o++ = '\n'; break;
        case 'r': *o++ = '\r'; break;
        case 't': *o++ = '\t'; break;
        case 'u': {
            unsigned code = 0;
            int ok = end - p >= 4;
            for (int i = 0; ok && i < 4; i++) {
                char h = p[i];
                code = code * 16 + (unsigned)(h >= '0' && h <= '9' ? h - '0'
                                              : h >= 'a' && h <= 'f' ? h - 'a' + 10
                                              : h >= 'A' && h <= 'F' ? h - 'A' + 10 : 0);
                ok = (h >= '0' && h <= '9') || (h >= 'a' && h <= 'f') || (h >= 'A' && h <= 'F');
            }
            if (!ok || code == 0 || (code >= 0xD800 && code < 0xE000)) {
                free(out);
                return NULL;
            }
            o = put_utf8(o, code);
            p += 4;
            break;
        }
        default: free(out); return NULL;
        }
    }
    *o = '\0';
    *pp = end + 1;
    return out;
}

/* Parse the array of strings at *pp into env->paths; 0 if malformed. */
static int parse_paths(const char **pp, PythonEnv *env)
{
    const char *p = skip_space(*pp + 1);
    while (*p != ']') {
        char *item = parse_string(&p);
        if (!item) return 0;
        char **grown = realloc(env->paths, (env->npaths + 1) * sizeof *grown);
        if (!grown) {
            free(item);
            return 0;
        }
        env->paths = grown;
        env->paths[env->npaths++] = item;
        p = skip_space(p);
        if (*p == ',') p = skip_space(p + 1);
        else if (*p != ']') return 0;
    }
    *pp = p + 1;
    return 1;
}

static int parse_env(const char *text, PythonEnv *env)
{
    const char *p = skip_space(text);
    if (*p++ != '{') return 0;
    p = skip_space(p);
    while (*p != '}') {
        char *key = parse_string(&p);
        if (!key) return 0;
        p = skip_space(p);
        int ok = *p++ == ':';
        p = skip_space(p);
        if (ok && *p == '[') {
            ok = strcmp(key, "sys_path") == 0 && env->npaths == 0 && parse_paths(&p, env);
        } else if (ok) {
            char *value = parse_string(&p);
            char **slot = strcmp(key, "library") == 0 ? &env->library
                        : strcmp(key, "executable") == 0 ? &env->executable : NULL;
            ok = value != NULL;
            if (slot && ok) {
                free(*slot);
                *slot = value;
            } else {
                free(value);
            }
        }
        free(key);
        if (!ok) return 0;
        p = skip_space(p);
        if (*p == ',') p = skip_space(p + 1);
        else if (*p != '}') return 0;
    }
    return env->library && env->executable && env->npaths > 0;
}

static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *text = NULL;
    long size = -1;
    if (fseek(f, 0, SEEK_END) == 0 && (size = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0)
        text = malloc((size_t)size + 1);
    if (text && fread(text, 1, (size_t)size, f) == (size_t)size) {
        text[size] = '\0';
    } else {
        free(text);
        text = NULL;
    }
    fclose(f);
    return text;
}

/* ------------------------------------------------------------------------------------ */
/* starting Python                                                                      */

static int python_running(void)
{
    int (*initialized)(void) = (int (*)(void))dlsym(RTLD_DEFAULT, "Py_IsInitialized");
    return initialized != NULL && initialized();
}

static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

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
} PythonApi;

/* Initialise the interpreter of env (isolated, its sys.path) and release the GIL. */
static int initialize_python(const PythonApi *py, const PythonEnv *env, char *err, size_t n)
{
    PyConfig config;
    py->InitIsolatedConfig(&config);
    PyStatus status = py->SetBytesString(&config, &config.program_name, env->executable);
    config.module_search_paths_set = 1;
    for (size_t i = 0; i < env->npaths && !py->StatusException(status); i++) {
        wchar_t *wide = py->DecodeLocale(env->paths[i], NULL);
        if (!wide) {
            snprintf(err, n, "cannot decode the path %s of " ENV_FILE, env->paths[i]);
            py->ConfigClear(&config);
            return 0;
        }
        status = py->ListAppend(&config.module_search_paths, wide);
        py->RawFree(wide);
    }
    if (!py->StatusException(status)) status = py->InitializeFromConfig(&config);
    py->ConfigClear(&config);
    if (py->StatusException(status)) {
        snprintf(err, n, "Python (%s) failed to start: %s%s%s", env->executable,
                 status.func ? status.func : "", status.func ? ": " : "",
                 status.err_msg ? status.err_msg : "unknown error");
        return 0;
    }
    py->SaveThread();
    return 1;
}

/* Load and start the Python of resources/python_env.json unless one is running. */
static int start_python(const char *root, char *err, size_t n)
{
    char path[PATH_MAX + 64];
    snprintf(path, sizeof path, "%s/%s", root, ENV_FILE);
    char *text = read_file(path);
    if (!text) {
        snprintf(err, n, "this FMU needs the Python environment it was built with and found no "
                 "record of it: cannot read %s", path);
        return 0;
    }
    PythonEnv env = {0};
    int ok = parse_env(text, &env);
    free(text);
    if (!ok) {
        snprintf(err, n, "%s is malformed (it needs \"library\", \"executable\" and \"sys_path\")", path);
        env_clear(&env);
        return 0;
    }
    const char *missing = !exists(env.executable) ? env.executable
                        : !exists(env.library) ? env.library : NULL;
    if (missing) {
        snprintf(err, n, "the Python environment this FMU was built with is missing: %s does not "
                 "exist (recorded in %s; install that environment or rebuild the FMU with "
                 "build_fmu.py in the Python environment of this machine)", missing, path);
        env_clear(&env);
        return 0;
    }
    void *lib = dlopen(env.library, RTLD_NOW | RTLD_GLOBAL); /* kept: Python stays loaded */
    PythonApi py;
    void *symbols[] = {
        dlsym(lib, "Py_IsInitialized"), dlsym(lib, "PyConfig_InitIsolatedConfig"),
        dlsym(lib, "PyConfig_SetBytesString"), dlsym(lib, "PyWideStringList_Append"),
        dlsym(lib, "Py_DecodeLocale"), dlsym(lib, "PyMem_RawFree"),
        dlsym(lib, "Py_InitializeFromConfig"), dlsym(lib, "PyConfig_Clear"),
        dlsym(lib, "PyStatus_Exception"), dlsym(lib, "PyEval_SaveThread"),
    };
    ok = lib != NULL;
    for (size_t i = 0; ok && i < sizeof symbols / sizeof *symbols; i++) ok = symbols[i] != NULL;
    if (!ok) {
        snprintf(err, n, "cannot load the Python library %s: %s", env.library,
                 lib ? "it lacks the PyConfig API (Python >= 3.8 needed)" : dlerror());
        env_clear(&env);
        return 0;
    }
    _Static_assert(sizeof py == sizeof symbols, "one symbol per PythonApi member");
    memcpy(&py, symbols, sizeof py);
    ok = py.IsInitialized() || initialize_python(&py, &env, err, n);
    env_clear(&env);
    return ok;
}

/* ------------------------------------------------------------------------------------ */
/* loading pythonfmu's library                                                          */

/* The folder of this library and the FMU's root folder (two levels up). */
static int own_folders(char *dir, char *root, size_t n)
{
    Dl_info info;
    if (!dladdr((void *)&own_folders, &info) || !info.dli_fname || !realpath(info.dli_fname, dir))
        return 0;
    char *slash = strrchr(dir, '/');
    if (!slash) return 0;
    *slash = '\0';
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
}

static int load_real(char *err, size_t n)
{
    char dir[PATH_MAX], root[PATH_MAX + 8], path[PATH_MAX + 32];
    if (!own_folders(dir, root, sizeof root)) {
        snprintf(err, n, "cannot find the folder of the FMU's binary");
        return 0;
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

/* Log msg through the host's logger: '%' doubled, as the logger formats printf-style. */
static void log_error(const fmi2CallbackFunctions *functions, fmi2String instance, const char *msg)
{
    char escaped[2 * MESSAGE_SIZE];
    size_t j = 0;
    for (size_t i = 0; msg[i] && j + 2 < sizeof escaped; i++) {
        if (msg[i] == '%') escaped[j++] = '%';
        escaped[j++] = msg[i];
    }
    escaped[j] = '\0';
    if (functions && functions->logger)
        functions->logger(functions->componentEnvironment, instance, fmi2Error, "logStatusError", escaped);
    else
        fprintf(stderr, "%s: %s\n", instance ? instance : "FMU", msg);
}

/* ------------------------------------------------------------------------------------ */
/* FMI 2.0 functions                                                                    */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    char err[MESSAGE_SIZE] = "";
    pthread_mutex_lock(&load_lock);
    int ok = real_handle != NULL || load_real(err, sizeof err);
    pthread_mutex_unlock(&load_lock);
    if (!ok) {
        log_error(functions, instanceName, err);
        return NULL;
    }
    return real.Instantiate(instanceName, fmuType, fmuGUID, fmuResourceLocation, functions, visible, loggingOn);
}

/* Forward to pythonfmu; before a successful fmi2Instantiate there is no component. */
#define FORWARD(name, ...) return real_handle ? real.name(__VA_ARGS__) : fmi2Error

void fmi2FreeInstance(fmi2Component c)
{
    if (real_handle) real.FreeInstance(c);
}

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String cat[])
{ FORWARD(SetDebugLogging, c, on, n, cat); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolDefined, fmi2Real tol, fmi2Real start,
                               fmi2Boolean stopDefined, fmi2Real stop)
{ FORWARD(SetupExperiment, c, tolDefined, tol, start, stopDefined, stop); }

fmi2Status fmi2EnterInitializationMode(fmi2Component c) { FORWARD(EnterInitializationMode, c); }
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { FORWARD(ExitInitializationMode, c); }
fmi2Status fmi2Terminate(fmi2Component c) { FORWARD(Terminate, c); }
fmi2Status fmi2Reset(fmi2Component c) { FORWARD(Reset, c); }

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[])
{ FORWARD(GetReal, c, vr, n, v); }
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[])
{ FORWARD(GetInteger, c, vr, n, v); }
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[])
{ FORWARD(GetBoolean, c, vr, n, v); }
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2String v[])
{ FORWARD(GetString, c, vr, n, v); }
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[])
{ FORWARD(SetReal, c, vr, n, v); }
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[])
{ FORWARD(SetInteger, c, vr, n, v); }
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[])
{ FORWARD(SetBoolean, c, vr, n, v); }
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2String v[])
{ FORWARD(SetString, c, vr, n, v); }

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s) { FORWARD(GetFMUstate, c, s); }
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) { FORWARD(SetFMUstate, c, s); }
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s) { FORWARD(FreeFMUstate, c, s); }
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *size)
{ FORWARD(SerializedFMUstateSize, c, s, size); }
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t size)
{ FORWARD(SerializeFMUstate, c, s, b, size); }
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t size, fmi2FMUstate *s)
{ FORWARD(DeSerializeFMUstate, c, b, size, s); }

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference z[], size_t nz, const fmi2Real dv[],
                                        fmi2Real dz[])
{ FORWARD(GetDirectionalDerivative, c, u, nu, z, nz, dv, dz); }

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                       const fmi2Integer order[], const fmi2Real v[])
{ FORWARD(SetRealInputDerivatives, c, vr, n, order, v); }
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer order[], fmi2Real v[])
{ FORWARD(GetRealOutputDerivatives, c, vr, n, order, v); }

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior)
{ FORWARD(DoStep, c, t, h, noSetPrior); }
fmi2Status fmi2CancelStep(fmi2Component c) { FORWARD(CancelStep, c); }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind k, fmi2Status *v) { FORWARD(GetStatus, c, k, v); }
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind k, fmi2Real *v) { FORWARD(GetRealStatus, c, k, v); }
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind k, fmi2Integer *v)
{ FORWARD(GetIntegerStatus, c, k, v); }
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind k, fmi2Boolean *v)
{ FORWARD(GetBooleanStatus, c, k, v); }
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind k, fmi2String *v)
{ FORWARD(GetStringStatus, c, k, v); }
