/*
 * A minimal FMI 2.0 Co-Simulation master for comparing one FMU's binaries across platforms:
 * the same C source is compiled for Linux x86_64 (gcc), Linux aarch64 (aarch64-linux-gnu-gcc,
 * run under qemu-aarch64) and Windows x86_64 (x86_64-w64-mingw32-gcc, run under wine). It
 * loads the library (dlopen / LoadLibrary), sets constant inputs, steps until the Boolean
 * output TOUCHDOWN_VR is true (or MAX_STEPS; a step ended early by touchdown returns
 * fmi2Discard), and prints every Real output's IEEE-754 bits in
 * hex, so the outputs of the platforms can be compared with `diff`.
 *
 * Usage: cross_master LIBRARY GUID STEP MAX_STEPS TOUCHDOWN_VR IN_VR=VALUE... -- OUT_VR...
 * Standalone C99: the few FMI 2.0 types it needs are declared here, as the standard has them.
 */
#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _WIN32
#include <windows.h>
#define LOAD(path) ((void *)LoadLibraryA(path))
#define SYMBOL(lib, name) ((void *)GetProcAddress((HMODULE)(lib), name))
#else
#include <dlfcn.h>
#define LOAD(path) dlopen(path, RTLD_NOW | RTLD_LOCAL)
#define SYMBOL(lib, name) dlsym(lib, name)
#endif

typedef void *fmi2Component;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Boolean;
typedef int fmi2Status;
typedef void (*fmi2Logger)(void *, const char *, fmi2Status, const char *, const char *, ...);
typedef struct {
    fmi2Logger logger;
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, fmi2Status);
    void *componentEnvironment;
} fmi2CallbackFunctions;

typedef fmi2Component (*InstantiateT)(const char *, int, const char *, const char *,
                                      const fmi2CallbackFunctions *, fmi2Boolean, fmi2Boolean);
typedef fmi2Status (*SetupExperimentT)(fmi2Component, fmi2Boolean, fmi2Real, fmi2Real,
                                       fmi2Boolean, fmi2Real);
typedef fmi2Status (*ComponentT)(fmi2Component);
typedef void (*FreeInstanceT)(fmi2Component);
typedef fmi2Status (*RealsT)(fmi2Component, const fmi2ValueReference *, size_t, fmi2Real *);
typedef fmi2Status (*SetRealT)(fmi2Component, const fmi2ValueReference *, size_t,
                               const fmi2Real *);
typedef fmi2Status (*GetBooleanT)(fmi2Component, const fmi2ValueReference *, size_t,
                                  fmi2Boolean *);
typedef fmi2Status (*DoStepT)(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean);

static void logger(void *env, const char *name, fmi2Status status, const char *category,
                   const char *message, ...) {
    va_list args;
    (void)env;
    fprintf(stderr, "[%s %d %s] ", name, status, category);
    va_start(args, message);
    vfprintf(stderr, message, args);
    va_end(args);
    fputc('\n', stderr);
}

static void *bind_function(void *lib, const char *name) {
    void *f = SYMBOL(lib, name);
    if (!f) {
        fprintf(stderr, "cross_master: %s is not exported\n", name);
        exit(2);
    }
    return f;
}

#define CHECK(call)                                                                            \
    do {                                                                                       \
        fmi2Status s_ = (call);                                                                \
        if (s_ > 1) {                                                                          \
            fprintf(stderr, "cross_master: %s returned %d\n", #call, s_);                      \
            return 1;                                                                          \
        }                                                                                      \
    } while (0)

int main(int argc, char **argv) {
    fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    fmi2ValueReference in_vr[64], out_vr[256], touchdown_vr;
    fmi2Real in_value[64], out_value[256], h, t = 0.0;
    size_t n_in = 0, n_out = 0, i;
    long steps, max_steps;
    fmi2Boolean touchdown = 0;
    int arg = 6;
    void *lib;
    fmi2Component c;

    if (argc < 7) {
        fprintf(stderr, "usage: %s LIBRARY GUID STEP MAX_STEPS TOUCHDOWN_VR IN_VR=VALUE... "
                        "-- OUT_VR...\n", argv[0]);
        return 2;
    }
    h = strtod(argv[3], NULL);
    max_steps = strtol(argv[4], NULL, 10);
    touchdown_vr = (fmi2ValueReference)strtoul(argv[5], NULL, 10);
    for (; arg < argc && strcmp(argv[arg], "--") != 0 && n_in < 64; arg++) {
        char *eq = strchr(argv[arg], '=');
        if (!eq) return 2;
        in_vr[n_in] = (fmi2ValueReference)strtoul(argv[arg], NULL, 10);
        in_value[n_in++] = strtod(eq + 1, NULL);
    }
    for (arg++; arg < argc && n_out < 256; arg++)
        out_vr[n_out++] = (fmi2ValueReference)strtoul(argv[arg], NULL, 10);

    lib = LOAD(argv[1]);
    if (!lib) {
        fprintf(stderr, "cross_master: cannot load %s\n", argv[1]);
        return 2;
    }
    c = ((InstantiateT)bind_function(lib, "fmi2Instantiate"))("cross", 1, argv[2], NULL, &callbacks, 0, 0);
    if (!c) {
        fprintf(stderr, "cross_master: fmi2Instantiate failed\n");
        return 1;
    }
    CHECK(((SetupExperimentT)bind_function(lib, "fmi2SetupExperiment"))(c, 0, 0.0, 0.0, 0, 0.0));
    CHECK(((ComponentT)bind_function(lib, "fmi2EnterInitializationMode"))(c));
    CHECK(((SetRealT)bind_function(lib, "fmi2SetReal"))(c, in_vr, n_in, in_value));
    CHECK(((ComponentT)bind_function(lib, "fmi2ExitInitializationMode"))(c));
    for (steps = 0; steps < max_steps && !touchdown; steps++) {
        CHECK(((SetRealT)bind_function(lib, "fmi2SetReal"))(c, in_vr, n_in, in_value));
        /* fmi2Discard: the step ended early, at touchdown (the FMU logs when). */
        fmi2Status status = ((DoStepT)bind_function(lib, "fmi2DoStep"))(c, t, h, 1);
        if (status > 2) {
            fprintf(stderr, "cross_master: fmi2DoStep returned %d at t = %g\n", status, t);
            return 1;
        }
        t = (double)(steps + 1) * h;
        CHECK(((GetBooleanT)bind_function(lib, "fmi2GetBoolean"))(c, &touchdown_vr, 1, &touchdown));
    }
    CHECK(((RealsT)bind_function(lib, "fmi2GetReal"))(c, out_vr, n_out, out_value));
    printf("steps %ld touchdown %d\n", steps, touchdown);
    for (i = 0; i < n_out; i++) {
        uint64_t bits;
        memcpy(&bits, &out_value[i], sizeof bits);
        printf("%u %016" PRIx64 " %.17g\n", out_vr[i], bits, out_value[i]);
    }
    CHECK(((ComponentT)bind_function(lib, "fmi2Terminate"))(c));
    ((FreeInstanceT)bind_function(lib, "fmi2FreeInstance"))(c);
    return touchdown ? 0 : 3;
}
