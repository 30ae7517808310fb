/*
 * A fixed-step Gauss-Seidel Co-Simulation master of several connected FMUs, FMI 2.0 or 3.0,
 * written once and compiled for every platform the FMUs carry a binary for: gcc (x86_64
 * Linux), aarch64-linux-gnu-gcc (run under qemu-aarch64), x86_64-w64-mingw32-gcc (run under
 * Wine). It prints every output of every FMU at every communication point as the IEEE-754
 * bits of a double, so that the runs of the platforms can be compared line by line
 * (tests/tests/same_bits.rs does).
 *
 * Usage: closed_loop_master PLAN OUT LOG
 *
 * PLAN is a text file, one directive per line (tests/tests/same_bits.rs writes it from the
 * harness's scenario and the FMUs' model descriptions, so this file needs no XML parser):
 *
 *   fmi 2|3                    the FMI version of every unit
 *   step H                     communication step (s)
 *   stop T                     stop time (s); the run starts at 0
 *   logging 0|1                loggingOn of every instance (1: every category)
 *   unit NAME                  begins a unit; units are exchanged in the order they come
 *   library PATH               (rest of the line) the unit's shared library
 *   token TEXT                 (rest of the line) fmuGUID / instantiationToken
 *   resources TEXT             (rest of the line) fmuResourceLocation / resourcePath;
 *                              without it, NULL
 *   instance TEXT              (rest of the line) instance name; default NAME
 *   param T VR N V1..VN        a parameter set before initialization
 *   output T VR N NAME         an output, N values (an FMI 3.0 array or a scalar)
 *   input T VR N S1..SN        an input, N values; each Si is UNIT:SLOT (the SLOT-th output
 *                              value of the UNIT-th unit, both from 0) or =VALUE (a value
 *                              kept as it is; FMI 3.0 writes an array whole)
 *
 * T is R (fmi2Real / fmi3Float64), I (fmi2Integer / fmi3Int32), E (an enumeration:
 * fmi2Integer / fmi3Int64) or B (fmi2Boolean / fmi3Boolean). Every value is held as a double
 * (integers and Booleans exactly) and printed as the 16 hex digits of its bits. H, T, Vi and
 * VALUE are written the same way, as bits: no C library's strtod can then round them
 * differently (msvcrt's is not correctly rounded).
 *
 * OUT (written in binary mode, so no platform changes a byte) holds
 *
 *   columns UNIT NAME...       once per unit: the printed values, in order
 *   K TIME UNIT BITS...        one line per unit and communication point K (TIME in bits)
 *   end completed|terminated UNIT|error UNIT FUNCTION STATUS
 *   freed                      after every instance was freed: the process lived on
 *
 * LOG holds one line per logger call: "INSTANCE|STATUS|CATEGORY|MESSAGE" (FMI 3.0 passes no
 * instance name to its logger: INSTANCE is the unit's).
 *
 * The exchange is the harness's Gauss-Seidel (harness/src/master/mod.rs): at each point every
 * unit in turn gets its inputs from the freshest outputs and is read; then every unit steps;
 * after the step, the units an earlier unit consumes are read again. FMI 3.0 forbids a get
 * after a set in Step Mode, so each unit is exchanged in Event Mode (docs/interface.md: "FMI
 * 3.0, Event Mode"), which reads the same values. A step that ends the simulation (FMI 2.0:
 * fmi2Discard with fmi2Terminated; FMI 3.0: terminateSimulation) is read and printed at its
 * last successful time and ends the run. Exit status: 0 completed or terminated by an FMU, 1
 * a call failed, 2 bad arguments, plan or library.
 */
#include <inttypes.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _WIN32
#include <windows.h>
#define LOAD(path) ((void *)LoadLibraryA(path))
#else
#include <dlfcn.h>
#define LOAD(path) dlopen(path, RTLD_NOW | RTLD_LOCAL)
#endif

/* The FMI types this master needs, as the standards declare them. */
typedef void *fmiInstance;
typedef unsigned int fmiValueReference;
typedef int fmi2Status;
typedef int fmi2Boolean;
typedef int fmi2Integer;
typedef void (*fmi2Logger)(void *, const char *, fmi2Status, const char *, const char *, ...);
typedef struct {
    fmi2Logger logger;
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, fmi2Status);
    void *componentEnvironment;
} fmi2CallbackFunctions;
typedef int fmi3Status;
typedef bool fmi3Boolean;
typedef void (*fmi3LogMessage)(void *, fmi3Status, const char *, const char *);

enum { STATUS_WARNING = 1, STATUS_DISCARD = 2, STATUS_ERROR = 3 };
enum { fmi2LastSuccessfulTime = 2, fmi2Terminated = 3 };

#define MAX_UNITS 8
#define MAX_VARS 128
#define MAX_VALUES 256
#define MAX_TEXT 1024

typedef struct {
    char type;
    fmiValueReference vr;
    size_t n;
    /* Inputs: source unit and slot per value (unit < 0: keep[]); outputs: first slot. */
    int from_unit[MAX_VALUES / 8];
    size_t from_slot[MAX_VALUES / 8];
    double keep[MAX_VALUES / 8];
    size_t slot;
    char name[64];
} Var;

typedef struct {
    char name[64];
    char library[MAX_TEXT], token[MAX_TEXT], resources[MAX_TEXT], instance_name[MAX_TEXT];
    int has_resources, has_instance_name;
    Var params[MAX_VARS], inputs[MAX_VARS], outputs[MAX_VARS];
    size_t n_params, n_inputs, n_outputs, n_slots;
    double values[MAX_VALUES];
    int consumed_by_earlier;
    void *lib;
    fmiInstance c;
} Unit;

static Unit units[MAX_UNITS];
static size_t n_units;
static int fmi_version = 2, logging_on;
static double step_size, stop_time;
static FILE *out, *log_file;

static void *symbol(Unit *u, const char *name) {
    void *f;
#ifdef _WIN32
    FARPROC p = GetProcAddress((HMODULE)u->lib, name);
    memcpy(&f, &p, sizeof f);
#else
    f = dlsym(u->lib, name);
#endif
    if (!f) {
        fprintf(stderr, "closed_loop_master: %s: %s is not exported\n", u->name, name);
        exit(2);
    }
    return f;
}

/* One function pointer type per signature; the name says which. */
#define FN(u, type, name) ((type)symbol(u, name))

static void fmi2_logger(void *env, const char *instance, fmi2Status status, const char *category,
                        const char *message, ...) {
    va_list args;
    (void)env;
    fprintf(log_file, "%s|%d|%s|", instance ? instance : "(null)", status,
            category ? category : "(null)");
    va_start(args, message);
    vfprintf(log_file, message, args);
    va_end(args);
    fputc('\n', log_file);
    fflush(log_file);
}

static void fmi3_logger(void *env, fmi3Status status, const char *category, const char *message) {
    fprintf(log_file, "%s|%d|%s|%s\n", ((Unit *)env)->name, status,
            category ? category : "(null)", message ? message : "(null)");
    fflush(log_file);
}

static void print_bits(double x) {
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    fprintf(out, " %016" PRIx64, bits);
}

static int failed(Unit *u, const char *function, int status) {
    size_t i;
    fprintf(out, "end error %s %s %d\n", u->name, function, status);
    fflush(out);
    /* After an error or a fatal status only freeing is certain to be legal. */
    for (i = 0; i < n_units; i++) {
        if (units[i].c) {
            if (fmi_version == 2)
                FN(&units[i], void (*)(fmiInstance), "fmi2FreeInstance")(units[i].c);
            else
                FN(&units[i], void (*)(fmiInstance), "fmi3FreeInstance")(units[i].c);
            units[i].c = NULL;
        }
    }
    fprintf(out, "freed\n");
    return 1;
}

#define CALL(u, function, call)                                                                \
    do {                                                                                       \
        int s_ = (call);                                                                       \
        if (s_ > STATUS_WARNING) return failed(u, function, s_);                               \
    } while (0)

/* Writes n values of one variable; FMI 2.0 variables are scalars (n = 1). */
static int set_values(Unit *u, char type, fmiValueReference vr, size_t n, const double *x) {
    size_t i;
    if (fmi_version == 2) {
        if (type == 'R') {
            return FN(u, fmi2Status (*)(fmiInstance, const fmiValueReference *, size_t,
                                        const double *), "fmi2SetReal")(u->c, &vr, 1, x);
        } else if (type == 'B') {
            fmi2Boolean b = x[0] != 0.0;
            return FN(u, fmi2Status (*)(fmiInstance, const fmiValueReference *, size_t,
                                        const fmi2Boolean *), "fmi2SetBoolean")(u->c, &vr, 1, &b);
        } else {
            fmi2Integer k = (fmi2Integer)x[0];
            return FN(u, fmi2Status (*)(fmiInstance, const fmiValueReference *, size_t,
                                        const fmi2Integer *), "fmi2SetInteger")(u->c, &vr, 1, &k);
        }
    }
    if (type == 'R') {
        return FN(u, fmi3Status (*)(fmiInstance, const fmiValueReference *, size_t,
                                    const double *, size_t), "fmi3SetFloat64")(u->c, &vr, 1, x, n);
    } else if (type == 'B') {
        fmi3Boolean b[MAX_VALUES];
        for (i = 0; i < n; i++) b[i] = x[i] != 0.0;
        return FN(u, fmi3Status (*)(fmiInstance, const fmiValueReference *, size_t,
                                    const fmi3Boolean *, size_t), "fmi3SetBoolean")(u->c, &vr, 1, b, n);
    } else if (type == 'E') {
        int64_t k[MAX_VALUES];
        for (i = 0; i < n; i++) k[i] = (int64_t)x[i];
        return FN(u, fmi3Status (*)(fmiInstance, const fmiValueReference *, size_t,
                                    const int64_t *, size_t), "fmi3SetInt64")(u->c, &vr, 1, k, n);
    } else {
        int32_t k[MAX_VALUES];
        for (i = 0; i < n; i++) k[i] = (int32_t)x[i];
        return FN(u, fmi3Status (*)(fmiInstance, const fmiValueReference *, size_t,
                                    const int32_t *, size_t), "fmi3SetInt32")(u->c, &vr, 1, k, n);
    }
}

static int get_values(Unit *u, char type, fmiValueReference vr, size_t n, double *x) {
    size_t i;
    int s;
    if (fmi_version == 2) {
        if (type == 'R') {
            return FN(u, fmi2Status (*)(fmiInstance, const fmiValueReference *, size_t, double *),
                      "fmi2GetReal")(u->c, &vr, 1, x);
        } else if (type == 'B') {
            fmi2Boolean b = 0;
            s = FN(u, fmi2Status (*)(fmiInstance, const fmiValueReference *, size_t, fmi2Boolean *),
                   "fmi2GetBoolean")(u->c, &vr, 1, &b);
            x[0] = b ? 1.0 : 0.0;
        } else {
            fmi2Integer k = 0;
            s = FN(u, fmi2Status (*)(fmiInstance, const fmiValueReference *, size_t, fmi2Integer *),
                   "fmi2GetInteger")(u->c, &vr, 1, &k);
            x[0] = (double)k;
        }
        return s;
    }
    if (type == 'R') {
        return FN(u, fmi3Status (*)(fmiInstance, const fmiValueReference *, size_t, double *,
                                    size_t), "fmi3GetFloat64")(u->c, &vr, 1, x, n);
    } else if (type == 'B') {
        fmi3Boolean b[MAX_VALUES] = {0};
        s = FN(u, fmi3Status (*)(fmiInstance, const fmiValueReference *, size_t, fmi3Boolean *,
                                 size_t), "fmi3GetBoolean")(u->c, &vr, 1, b, n);
        for (i = 0; i < n; i++) x[i] = b[i] ? 1.0 : 0.0;
    } else if (type == 'E') {
        int64_t k[MAX_VALUES] = {0};
        s = FN(u, fmi3Status (*)(fmiInstance, const fmiValueReference *, size_t, int64_t *,
                                 size_t), "fmi3GetInt64")(u->c, &vr, 1, k, n);
        for (i = 0; i < n; i++) x[i] = (double)k[i];
    } else {
        int32_t k[MAX_VALUES] = {0};
        s = FN(u, fmi3Status (*)(fmiInstance, const fmiValueReference *, size_t, int32_t *,
                                 size_t), "fmi3GetInt32")(u->c, &vr, 1, k, n);
        for (i = 0; i < n; i++) x[i] = (double)k[i];
    }
    return s;
}

/* 0 or the failed call's status; the function's name in *function. */
static int set_inputs(Unit *u, const char **function) {
    size_t i, j;
    double x[MAX_VALUES];
    *function = fmi_version == 2 ? "fmi2Set*" : "fmi3Set*";
    for (i = 0; i < u->n_inputs; i++) {
        Var *v = &u->inputs[i];
        int s;
        for (j = 0; j < v->n; j++)
            x[j] = v->from_unit[j] < 0 ? v->keep[j] : units[v->from_unit[j]].values[v->from_slot[j]];
        s = set_values(u, v->type, v->vr, v->n, x);
        if (s > STATUS_WARNING) return s;
    }
    return 0;
}

static int get_outputs(Unit *u, const char **function) {
    size_t i;
    *function = fmi_version == 2 ? "fmi2Get*" : "fmi3Get*";
    for (i = 0; i < u->n_outputs; i++) {
        Var *v = &u->outputs[i];
        int s = get_values(u, v->type, v->vr, v->n, &u->values[v->slot]);
        if (s > STATUS_WARNING) return s;
    }
    return 0;
}

static void print_row(long k, double t) {
    size_t i, j;
    for (i = 0; i < n_units; i++) {
        fprintf(out, "%ld", k);
        print_bits(t);
        fprintf(out, " %s", units[i].name);
        for (j = 0; j < units[i].n_slots; j++) print_bits(units[i].values[j]);
        fputc('\n', out);
    }
}

/* A double written as the 16 hex digits of its bits; moves *p past them. */
static double read_bits(char **p) {
    uint64_t bits = (uint64_t)strtoull(*p, p, 16);
    double x;
    memcpy(&x, &bits, sizeof x);
    return x;
}

/* Copies the rest of a directive's line, without its line end. */
static void rest_of_line(char *dst, const char *src) {
    size_t n;
    while (*src == ' ') src++;
    n = strcspn(src, "\r\n");
    if (n >= MAX_TEXT) n = MAX_TEXT - 1;
    memcpy(dst, src, n);
    dst[n] = '\0';
}

/* Reads "T VR N" and moves *p past it; 0 when malformed. */
static int read_var_head(Var *v, char **p) {
    char type;
    unsigned vr;
    unsigned long n;
    int used = 0;
    if (sscanf(*p, " %c %u %lu%n", &type, &vr, &n, &used) != 3 || !strchr("RIEB", type) ||
        n == 0 || n > MAX_VALUES / 8)
        return 0;
    v->type = type;
    v->vr = vr;
    v->n = n;
    *p += used;
    return 1;
}

static int read_plan(const char *path) {
    char line[4 * MAX_TEXT];
    FILE *f = fopen(path, "rb");
    Unit *u = NULL;
    if (!f) return 0;
    while (fgets(line, sizeof line, f)) {
        char key[32];
        int used = 0;
        char *p;
        size_t j;
        if (sscanf(line, "%31s%n", key, &used) != 1) continue;
        p = line + used;
        if (!strcmp(key, "fmi")) fmi_version = atoi(p);
        else if (!strcmp(key, "step")) step_size = read_bits(&p);
        else if (!strcmp(key, "stop")) stop_time = read_bits(&p);
        else if (!strcmp(key, "logging")) logging_on = atoi(p);
        else if (!strcmp(key, "unit")) {
            if (n_units == MAX_UNITS) return 0;
            u = &units[n_units++];
            if (sscanf(p, "%63s", u->name) != 1) return 0;
        } else if (!u) return 0;
        else if (!strcmp(key, "library")) rest_of_line(u->library, p);
        else if (!strcmp(key, "token")) rest_of_line(u->token, p);
        else if (!strcmp(key, "resources")) {
            rest_of_line(u->resources, p);
            u->has_resources = 1;
        } else if (!strcmp(key, "instance")) {
            rest_of_line(u->instance_name, p);
            u->has_instance_name = 1;
        } else if (!strcmp(key, "param")) {
            Var *v = &u->params[u->n_params];
            if (u->n_params == MAX_VARS || !read_var_head(v, &p)) return 0;
            for (j = 0; j < v->n; j++) v->keep[j] = read_bits(&p);
            u->n_params++;
        } else if (!strcmp(key, "output")) {
            Var *v = &u->outputs[u->n_outputs];
            if (u->n_outputs == MAX_VARS || !read_var_head(v, &p)) return 0;
            if (sscanf(p, "%63s", v->name) != 1 || u->n_slots + v->n > MAX_VALUES) return 0;
            v->slot = u->n_slots;
            u->n_slots += v->n;
            u->n_outputs++;
        } else if (!strcmp(key, "input")) {
            Var *v = &u->inputs[u->n_inputs];
            if (u->n_inputs == MAX_VARS || !read_var_head(v, &p)) return 0;
            for (j = 0; j < v->n; j++) {
                int from, got = 0;
                unsigned long slot;
                while (*p == ' ') p++;
                if (*p == '=') {
                    v->from_unit[j] = -1;
                    p++;
                    v->keep[j] = read_bits(&p);
                } else if (sscanf(p, "%d:%lu%n", &from, &slot, &got) == 2 && from >= 0) {
                    v->from_unit[j] = from;
                    v->from_slot[j] = slot;
                    p += got;
                } else
                    return 0;
            }
            u->n_inputs++;
        } else
            return 0;
    }
    fclose(f);
    return n_units > 0 && step_size > 0.0 && (fmi_version == 2 || fmi_version == 3);
}

/* Every source of an input must exist; a unit read by an earlier one is read after its step. */
static int check_plan(void) {
    size_t i, k, j;
    for (i = 0; i < n_units; i++) {
        for (k = 0; k < units[i].n_inputs; k++) {
            Var *v = &units[i].inputs[k];
            for (j = 0; j < v->n; j++) {
                int from = v->from_unit[j];
                if (from < 0) continue;
                if ((size_t)from >= n_units || v->from_slot[j] >= units[from].n_slots) return 0;
                if ((size_t)from > i) units[from].consumed_by_earlier = 1;
            }
        }
    }
    return 1;
}

static int instantiate(Unit *u) {
    static fmi2CallbackFunctions callbacks = {fmi2_logger, calloc, free, NULL, NULL};
    const char *name = u->has_instance_name ? u->instance_name : u->name;
    const char *resources = u->has_resources ? u->resources : NULL;
    size_t i;
    u->lib = LOAD(u->library);
    if (!u->lib) {
        fprintf(stderr, "closed_loop_master: cannot load %s\n", u->library);
        exit(2);
    }
    if (fmi_version == 2) {
        u->c = FN(u, fmiInstance (*)(const char *, int, const char *, const char *,
                                     const fmi2CallbackFunctions *, fmi2Boolean, fmi2Boolean),
                  "fmi2Instantiate")(name, 1, u->token, resources, &callbacks, 0, logging_on);
        if (!u->c) return failed(u, "fmi2Instantiate", STATUS_ERROR);
        CALL(u, "fmi2SetupExperiment",
             FN(u, fmi2Status (*)(fmiInstance, fmi2Boolean, double, double, fmi2Boolean, double),
                "fmi2SetupExperiment")(u->c, 0, 0.0, 0.0, 1, stop_time));
    } else {
        u->c = FN(u, fmiInstance (*)(const char *, const char *, const char *, fmi3Boolean,
                                     fmi3Boolean, fmi3Boolean, fmi3Boolean,
                                     const fmiValueReference *, size_t, void *, fmi3LogMessage,
                                     void *),
                  "fmi3InstantiateCoSimulation")(name, u->token, resources, false, logging_on != 0,
                                                 true, false, NULL, 0, u, fmi3_logger, NULL);
        if (!u->c) return failed(u, "fmi3InstantiateCoSimulation", STATUS_ERROR);
    }
    for (i = 0; i < u->n_params; i++) {
        Var *v = &u->params[i];
        CALL(u, "setting a parameter", set_values(u, v->type, v->vr, v->n, v->keep));
    }
    if (fmi_version == 2)
        CALL(u, "fmi2EnterInitializationMode",
             FN(u, fmi2Status (*)(fmiInstance), "fmi2EnterInitializationMode")(u->c));
    else
        CALL(u, "fmi3EnterInitializationMode",
             FN(u, fmi3Status (*)(fmiInstance, fmi3Boolean, double, double, fmi3Boolean, double),
                "fmi3EnterInitializationMode")(u->c, false, 0.0, 0.0, true, stop_time));
    return 0;
}

/* FMI 3.0: out of Event Mode into Step Mode; *terminate when an FMU asks to stop. */
static int enter_step_mode(Unit *u, int *terminate) {
    fmi3Boolean need_update = true, term = false, nominals, values, next_defined;
    double next;
    while (need_update) {
        CALL(u, "fmi3UpdateDiscreteStates",
             FN(u, fmi3Status (*)(fmiInstance, fmi3Boolean *, fmi3Boolean *, fmi3Boolean *,
                                  fmi3Boolean *, fmi3Boolean *, double *),
                "fmi3UpdateDiscreteStates")(u->c, &need_update, &term, &nominals, &values,
                                            &next_defined, &next));
        if (term) {
            *terminate = 1;
            return 0;
        }
    }
    CALL(u, "fmi3EnterStepMode", FN(u, fmi3Status (*)(fmiInstance), "fmi3EnterStepMode")(u->c));
    return 0;
}

static int enter_event_mode(Unit *u) {
    CALL(u, "fmi3EnterEventMode", FN(u, fmi3Status (*)(fmiInstance), "fmi3EnterEventMode")(u->c));
    return 0;
}

/* Gauss-Seidel at one communication point: each unit's inputs, then its outputs. */
static int exchange(int in_step_mode) {
    size_t i;
    const char *function;
    int s;
    for (i = 0; i < n_units; i++) {
        if (fmi_version == 3 && in_step_mode && enter_event_mode(&units[i])) return 1;
        if ((s = set_inputs(&units[i], &function)) || (s = get_outputs(&units[i], &function)))
            return failed(&units[i], function, s);
    }
    return 0;
}

static int run(void) {
    size_t i;
    long k, steps;
    double ratio = stop_time / step_size;
    const char *function;
    int s;

    /* The harness's step count: the last step is shortened to land on the stop time. */
    steps = (long)(ratio + 0.5);
    if (!(ratio - (double)steps < 1e-9 * ratio && (double)steps - ratio < 1e-9 * ratio))
        steps = (long)ratio + 1;
    for (i = 0; i < n_units; i++)
        if (instantiate(&units[i])) return 1;
    /* Initialization Mode: sets and gets in any order; the harness exchanges twice. */
    for (i = 0; i < n_units; i++)
        if ((s = get_outputs(&units[i], &function))) return failed(&units[i], function, s);
    if (exchange(0)) return 1;
    for (i = 0; i < n_units; i++) {
        if (fmi_version == 2)
            CALL(&units[i], "fmi2ExitInitializationMode",
                 FN(&units[i], fmi2Status (*)(fmiInstance), "fmi2ExitInitializationMode")(units[i].c));
        else
            CALL(&units[i], "fmi3ExitInitializationMode",
                 FN(&units[i], fmi3Status (*)(fmiInstance), "fmi3ExitInitializationMode")(units[i].c));
    }
    for (i = 0; i < n_units; i++)
        if ((s = get_outputs(&units[i], &function))) return failed(&units[i], function, s);
    /* FMI 3.0 with eventModeUsed: after initialization every instance is in Event Mode. */
    for (k = 0; k < steps; k++) {
        double t = (double)k * step_size;
        double h = k + 1 == steps ? stop_time - t : step_size;
        int terminate = 0;
        if (exchange(k > 0)) return 1;
        print_row(k, t);
        if (fmi_version == 3) {
            for (i = 0; i < n_units; i++) {
                if (enter_step_mode(&units[i], &terminate)) return 1;
                if (terminate) {
                    fprintf(out, "end terminated %s\n", units[i].name);
                    return 0;
                }
            }
        }
        for (i = 0; i < n_units; i++) {
            Unit *u = &units[i];
            double last = t + h;
            if (fmi_version == 2) {
                s = FN(u, fmi2Status (*)(fmiInstance, double, double, fmi2Boolean), "fmi2DoStep")(
                    u->c, t, h, 1);
                if (s == STATUS_DISCARD) {
                    fmi2Boolean terminated = 0;
                    CALL(u, "fmi2GetBooleanStatus",
                         FN(u, fmi2Status (*)(fmiInstance, int, fmi2Boolean *),
                            "fmi2GetBooleanStatus")(u->c, fmi2Terminated, &terminated));
                    if (!terminated) return failed(u, "fmi2DoStep", s);
                    CALL(u, "fmi2GetRealStatus",
                         FN(u, fmi2Status (*)(fmiInstance, int, double *), "fmi2GetRealStatus")(
                             u->c, fmi2LastSuccessfulTime, &last));
                    terminate = 1;
                } else if (s > STATUS_WARNING)
                    return failed(u, "fmi2DoStep", s);
            } else {
                fmi3Boolean event = false, term = false, early = false;
                s = FN(u, fmi3Status (*)(fmiInstance, double, double, fmi3Boolean, fmi3Boolean *,
                                         fmi3Boolean *, fmi3Boolean *, double *),
                       "fmi3DoStep")(u->c, t, h, true, &event, &term, &early, &last);
                if (s > STATUS_WARNING) return failed(u, "fmi3DoStep", s);
                terminate = term;
            }
            if (terminate) {
                if ((s = get_outputs(u, &function))) return failed(u, function, s);
                print_row(k + 1, last);
                fprintf(out, "end terminated %s\n", u->name);
                return 0;
            }
        }
        for (i = 0; i < n_units; i++)
            if (units[i].consumed_by_earlier && (s = get_outputs(&units[i], &function)))
                return failed(&units[i], function, s);
    }
    if (exchange(steps > 0)) return 1;
    print_row(steps, stop_time);
    fprintf(out, "end completed\n");
    return 0;
}

int main(int argc, char **argv) {
    size_t i, j;
    int result;
    if (argc != 4) {
        fprintf(stderr, "usage: %s PLAN OUT LOG\n", argv[0]);
        return 2;
    }
    if (!read_plan(argv[1]) || !check_plan()) {
        fprintf(stderr, "closed_loop_master: %s is not a valid plan\n", argv[1]);
        return 2;
    }
    out = fopen(argv[2], "wb");
    log_file = fopen(argv[3], "wb");
    if (!out || !log_file) {
        fprintf(stderr, "closed_loop_master: cannot write %s or %s\n", argv[2], argv[3]);
        return 2;
    }
    for (i = 0; i < n_units; i++) {
        fprintf(out, "columns %s", units[i].name);
        for (j = 0; j < units[i].n_outputs; j++) {
            const Var *v = &units[i].outputs[j];
            size_t e;
            if (v->n == 1) fprintf(out, " %s", v->name);
            else
                for (e = 0; e < v->n; e++) fprintf(out, " %s[%lu]", v->name, (unsigned long)(e + 1));
        }
        fputc('\n', out);
    }
    result = run();
    if (result == 0) {
        for (i = 0; i < n_units; i++) {
            Unit *u = &units[i];
            if (fmi_version == 2) {
                FN(u, fmi2Status (*)(fmiInstance), "fmi2Terminate")(u->c);
                FN(u, void (*)(fmiInstance), "fmi2FreeInstance")(u->c);
            } else {
                FN(u, fmi3Status (*)(fmiInstance), "fmi3Terminate")(u->c);
                FN(u, void (*)(fmiInstance), "fmi3FreeInstance")(u->c);
            }
            u->c = NULL;
        }
        fprintf(out, "freed\n");
    }
    fclose(out);
    fclose(log_file);
    return result;
}
