/*
 * The paper flight's closed loop (LanderGnc + LanderPlant) in a native C master that knows
 * nothing of the project: it calls the FMUs' FMI 2.0 or FMI 3.0 Co-Simulation functions
 * through the official headers' function types (dlsym), as a user's master does, and lists
 * the value references the way the chosen variant says. `call_orders count` compiles it
 * (`src/c_master.rs`) and counts its `run_loop` under callgrind.
 *
 * Usage: list_orders_master KEY=VALUE...
 *
 *   fmi=2|3  order=read-then-step|step-then-read|jacobi  steps=N  step=BITS
 *   variant=contract|sorted|reversed|shuffled|reshuffled|per-value
 *   gnc=LIB plant=LIB  gnc_token=TEXT plant_token=TEXT  gnc_res=URI plant_res=URI
 *   nav_gnc=VR,... nav_plant=VR,... nav_sizes=N,...   (the navigation signals, contract order)
 *   cmd_gnc=VR,... cmd_plant=VR,... cmd_sizes=N,...   (the commands, contract order)
 *   law=VR  gnc_init=VR,... gnc_init_values=BITS,...  plant_init=VR,... plant_init_values=BITS,...
 *
 * A list names variables in the signal contract's order (r, v, q, omega, mass; thrust,
 * torque): FMI 2.0 one reference per scalar (sizes all 1), FMI 3.0 one per array. The
 * variants (each list on its own, the pairs of reference and value kept together):
 *
 *   contract    the contract's order
 *   sorted      by value reference, ascending
 *   reversed    the contract's order reversed
 *   shuffled    a fixed pseudo-random order (seeded, the same every run)
 *   reshuffled  a new order at every step: 64 seeded orders in turn, each list rebuilt
 *   per-value   contract order, one variable per call (FMI 2.0: one scalar; FMI 3.0: one
 *               array, whole)
 *
 * Like any generic master, it keeps the exchanged signals in contract order and maps each
 * list's values to them (one indexed copy per value, in every variant, so the master's own
 * share is the same in all). It prints the plant's 14 navigation outputs after the flight
 * as bit patterns ("bits ..."). Exit status: 0 flown, 1 a call failed, 2 bad arguments.
 */
#include <dlfcn.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2FunctionTypes.h"
#include "fmi3FunctionTypes.h"

#define MAX_VARS 16
#define MAX_VALUES 32
#define ORDERS 64

/* A list of variables as the master passes it, and where each value goes in the signal. */
typedef struct {
    size_t n;                      /* variables */
    unsigned int vr[MAX_VARS];     /* value references, in the list's order */
    size_t size[MAX_VARS];         /* values per variable */
    size_t offset[MAX_VARS];       /* first value of each variable in the signal */
    size_t nvalues;                /* values in all */
    size_t element[MAX_VALUES];    /* the list's k-th value is the signal's element[k]-th */
} List;

typedef struct {
    void *instance;
    fmi2SetRealTYPE *set2;
    fmi2GetRealTYPE *get2;
    fmi2DoStepTYPE *step2;
    fmi3SetFloat64TYPE *set3;
    fmi3GetFloat64TYPE *get3;
    fmi3DoStepTYPE *step3;
} Unit;

static int fmi = 2;

static void die(const char *what) {
    fprintf(stderr, "list_orders_master: %s\n", what);
    exit(2);
}

static const char *arg(int argc, char **argv, const char *key) {
    size_t k = strlen(key);
    for (int i = 1; i < argc; i++) {
        if (strncmp(argv[i], key, k) == 0 && argv[i][k] == '=') {
            return argv[i] + k + 1;
        }
    }
    fprintf(stderr, "list_orders_master: missing %s=\n", key);
    exit(2);
}

/* A comma-separated list of unsigned numbers (base 10, or 16 with `hex`). */
static size_t numbers(const char *text, uint64_t *out, size_t most, int hex) {
    size_t n = 0;
    while (*text) {
        char *end;
        if (n == most) die("a list is too long");
        out[n++] = strtoull(text, &end, hex ? 16 : 10);
        if (end == text) die("not a number in a list");
        text = *end == ',' ? end + 1 : end;
    }
    return n;
}

static double from_bits(uint64_t bits) {
    double x;
    memcpy(&x, &bits, sizeof x);
    return x;
}

/* The contract-ordered list of `vrs` (with `sizes`). */
static List contract(const char *vrs, const char *sizes) {
    uint64_t v[MAX_VARS], s[MAX_VARS];
    List l = {0};
    l.n = numbers(vrs, v, MAX_VARS, 0);
    if (numbers(sizes, s, MAX_VARS, 0) != l.n) die("sizes do not match the references");
    for (size_t i = 0; i < l.n; i++) {
        l.vr[i] = (unsigned int)v[i];
        l.size[i] = (size_t)s[i];
        l.offset[i] = l.nvalues;
        for (size_t e = 0; e < l.size[i]; e++) {
            if (l.nvalues == MAX_VALUES) die("too many values");
            l.element[l.nvalues++] = l.offset[i] + e;
        }
    }
    return l;
}

/* `c`'s variables in the order `perm` (perm[i]: the contract position of the i-th). */
static List permuted(const List *c, const size_t *perm) {
    List l = {0};
    l.n = c->n;
    for (size_t i = 0; i < c->n; i++) {
        size_t j = perm[i];
        l.vr[i] = c->vr[j];
        l.size[i] = c->size[j];
        l.offset[i] = c->offset[j];
        for (size_t e = 0; e < c->size[j]; e++) l.element[l.nvalues++] = c->offset[j] + e;
    }
    return l;
}

static uint64_t seed = 0x9E3779B97F4A7C15u;

/* xorshift64*: the same orders on every run and platform. */
static uint64_t next_random(void) {
    seed ^= seed >> 12;
    seed ^= seed << 25;
    seed ^= seed >> 27;
    return seed * 0x2545F4914F6CDD1Du;
}

/* The list `c` as `variant` orders it (each call of a shuffling variant, a new order). */
static List ordered(const List *c, const char *variant) {
    size_t perm[MAX_VARS];
    size_t n = c->n;
    for (size_t i = 0; i < n; i++) perm[i] = i;
    if (strcmp(variant, "sorted") == 0) {
        for (size_t i = 1; i < n; i++) {
            for (size_t j = i; j > 0 && c->vr[perm[j - 1]] > c->vr[perm[j]]; j--) {
                size_t t = perm[j];
                perm[j] = perm[j - 1];
                perm[j - 1] = t;
            }
        }
    } else if (strcmp(variant, "reversed") == 0) {
        for (size_t i = 0; i < n; i++) perm[i] = n - 1 - i;
    } else if (strcmp(variant, "shuffled") == 0 || strcmp(variant, "reshuffled") == 0) {
        for (size_t i = n; i > 1; i--) {
            size_t j = (size_t)(next_random() % i);
            size_t t = perm[i - 1];
            perm[i - 1] = perm[j];
            perm[j] = t;
        }
    } else if (strcmp(variant, "contract") != 0 && strcmp(variant, "per-value") != 0) {
        die("unknown variant");
    }
    return permuted(c, perm);
}

static void logger2(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status,
                 fmi2String category, fmi2String message, ...) {
    (void)env;
    va_list args;
    va_start(args, message);
    fprintf(stderr, "%s [%d] %s: ", name ? name : "?", (int)status, category ? category : "");
    vfprintf(stderr, message, args);
    fputc('\n', stderr);
    va_end(args);
}

static void logger3(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category,
                 fmi3String message) {
    fprintf(stderr, "%s [%d] %s: %s\n", (const char *)env, (int)status,
            category ? category : "", message);
}

static const fmi2CallbackFunctions callbacks2 = {logger2, calloc, free, NULL, NULL};

static void *symbol(void *library, const char *name) {
    void *f = dlsym(library, name);
    if (!f) {
        fprintf(stderr, "list_orders_master: no %s\n", name);
        exit(2);
    }
    return f;
}

static void check(int status, const char *what) {
    if (status != 0) {
        fprintf(stderr, "list_orders_master: %s returned status %d\n", what, status);
        exit(1);
    }
}

/* Instantiates and initializes one FMU for the paper flight. */
static Unit load(int argc, char **argv, const char *name, double stop) {
    char key[32];
    snprintf(key, sizeof key, "%s", name);
    void *library = dlopen(arg(argc, argv, key), RTLD_NOW | RTLD_LOCAL);
    if (!library) die(dlerror());
    snprintf(key, sizeof key, "%s_token", name);
    const char *token = arg(argc, argv, key);
    snprintf(key, sizeof key, "%s_res", name);
    const char *resources = arg(argc, argv, key);
    Unit u = {0};
    if (fmi == 2) {
        fmi2InstantiateTYPE *instantiate = (fmi2InstantiateTYPE *)symbol(library, "fmi2Instantiate");
        u.set2 = (fmi2SetRealTYPE *)symbol(library, "fmi2SetReal");
        u.get2 = (fmi2GetRealTYPE *)symbol(library, "fmi2GetReal");
        u.step2 = (fmi2DoStepTYPE *)symbol(library, "fmi2DoStep");
        u.instance = instantiate(name, fmi2CoSimulation, token, resources, &callbacks2,
                                 fmi2False, fmi2False);
        if (!u.instance) die("fmi2Instantiate returned NULL");
        fmi2SetupExperimentTYPE *setup = (fmi2SetupExperimentTYPE *)symbol(library, "fmi2SetupExperiment");
        check(setup(u.instance, fmi2False, 0.0, 0.0, fmi2True, stop), "fmi2SetupExperiment");
        fmi2EnterInitializationModeTYPE *enter =
            (fmi2EnterInitializationModeTYPE *)symbol(library, "fmi2EnterInitializationMode");
        check(enter(u.instance), "fmi2EnterInitializationMode");
    } else {
        fmi3InstantiateCoSimulationTYPE *instantiate =
            (fmi3InstantiateCoSimulationTYPE *)symbol(library, "fmi3InstantiateCoSimulation");
        u.set3 = (fmi3SetFloat64TYPE *)symbol(library, "fmi3SetFloat64");
        u.get3 = (fmi3GetFloat64TYPE *)symbol(library, "fmi3GetFloat64");
        u.step3 = (fmi3DoStepTYPE *)symbol(library, "fmi3DoStep");
        u.instance = instantiate(name, token, resources, fmi3False, fmi3False, fmi3False,
                                 fmi3False, NULL, 0, (void *)name, logger3, NULL);
        if (!u.instance) die("fmi3InstantiateCoSimulation returned NULL");
        fmi3EnterInitializationModeTYPE *enter =
            (fmi3EnterInitializationModeTYPE *)symbol(library, "fmi3EnterInitializationMode");
        check(enter(u.instance, fmi3False, 0.0, 0.0, fmi3True, stop),
              "fmi3EnterInitializationMode");
    }
    return u;
}

/* Sets the Reals `vrs_key` to `values_key` (bit patterns) during initialization. */
static void initial_reals(int argc, char **argv, Unit *u, const char *vrs_key,
                          const char *values_key) {
    uint64_t vrs[MAX_VARS], bits[MAX_VALUES];
    unsigned int vr[MAX_VARS];
    double values[MAX_VALUES];
    size_t n = numbers(arg(argc, argv, vrs_key), vrs, MAX_VARS, 0);
    size_t nv = numbers(arg(argc, argv, values_key), bits, MAX_VALUES, 1);
    for (size_t i = 0; i < n; i++) vr[i] = (unsigned int)vrs[i];
    for (size_t i = 0; i < nv; i++) values[i] = from_bits(bits[i]);
    if (fmi == 2) {
        if (n != nv) die("one value per FMI 2.0 reference");
        check(u->set2(u->instance, vr, n, values), "fmi2SetReal (initial)");
    } else {
        check(u->set3(u->instance, vr, n, values, nv), "fmi3SetFloat64 (initial)");
    }
}

static inline int set_list(const Unit *u, const List *l, const double *signal) {
    double buffer[MAX_VALUES];
    for (size_t k = 0; k < l->nvalues; k++) buffer[k] = signal[l->element[k]];
    if (fmi == 2) return u->set2(u->instance, l->vr, l->n, buffer);
    return u->set3(u->instance, l->vr, l->n, buffer, l->nvalues);
}

static inline int get_list(const Unit *u, const List *l, double *signal) {
    double buffer[MAX_VALUES];
    int status = fmi == 2 ? u->get2(u->instance, l->vr, l->n, buffer)
                          : u->get3(u->instance, l->vr, l->n, buffer, l->nvalues);
    for (size_t k = 0; k < l->nvalues; k++) signal[l->element[k]] = buffer[k];
    return status;
}

/* One variable per call, straight to and from the signal. */
static inline int set_each(const Unit *u, const List *l, const double *signal) {
    int status = 0;
    for (size_t i = 0; i < l->n; i++) {
        const double *v = signal + l->offset[i];
        status |= fmi == 2 ? u->set2(u->instance, &l->vr[i], 1, v)
                           : u->set3(u->instance, &l->vr[i], 1, v, l->size[i]);
    }
    return status;
}

static inline int get_each(const Unit *u, const List *l, double *signal) {
    int status = 0;
    for (size_t i = 0; i < l->n; i++) {
        double *v = signal + l->offset[i];
        status |= fmi == 2 ? u->get2(u->instance, &l->vr[i], 1, v)
                           : u->get3(u->instance, &l->vr[i], 1, v, l->size[i]);
    }
    return status;
}

static inline int step(const Unit *u, double t, double h) {
    if (fmi == 2) return u->step2(u->instance, t, h, fmi2True);
    fmi3Boolean event, terminate, early;
    fmi3Float64 last;
    return u->step3(u->instance, t, h, fmi3True, &event, &terminate, &early, &last);
}

/* The lists of one step: navigation into the GNC, out of the plant; commands out of the
 * GNC, into the plant. */
typedef struct {
    List nav_in, nav_out, cmd_out, cmd_in;
} Lists;

enum { READ_THEN_STEP, STEP_THEN_READ, JACOBI };

#define SET(u, l, s) (each ? set_each(u, l, s) : set_list(u, l, s))
#define GET(u, l, s) (each ? get_each(u, l, s) : get_list(u, l, s))

/* The measured flight: `steps` steps of `h` in `order`; `lists[k % nlists]` at step k.
 * Returns the first failing status (0: flown). */
__attribute__((noinline)) int run_loop(const Unit *gnc, const Unit *plant, const Lists *lists,
                                       size_t nlists, int order, int each, size_t steps, double h,
                                       double *nav, double *cmd) {
    int status = GET(plant, &lists[0].nav_out, nav);
    if (order != READ_THEN_STEP) {
        status |= SET(gnc, &lists[0].nav_in, nav);
        status |= GET(gnc, &lists[0].cmd_out, cmd);
    }
    for (size_t k = 0; k < steps && status == 0; k++) {
        const Lists *l = &lists[k % nlists];
        double t = (double)k * h;
        switch (order) {
        case READ_THEN_STEP:
            status |= SET(gnc, &l->nav_in, nav);
            status |= GET(gnc, &l->cmd_out, cmd);
            status |= SET(plant, &l->cmd_in, cmd);
            status |= step(gnc, t, h);
            status |= step(plant, t, h);
            status |= GET(plant, &l->nav_out, nav);
            break;
        case STEP_THEN_READ:
            status |= SET(gnc, &l->nav_in, nav);
            status |= step(gnc, t, h);
            status |= GET(gnc, &l->cmd_out, cmd);
            status |= SET(plant, &l->cmd_in, cmd);
            status |= step(plant, t, h);
            status |= GET(plant, &l->nav_out, nav);
            break;
        default:
            status |= SET(gnc, &l->nav_in, nav);
            status |= SET(plant, &l->cmd_in, cmd);
            status |= step(gnc, t, h);
            status |= step(plant, t, h);
            status |= GET(gnc, &l->cmd_out, cmd);
            status |= GET(plant, &l->nav_out, nav);
            break;
        }
    }
    return status;
}

int main(int argc, char **argv) {
    fmi = atoi(arg(argc, argv, "fmi"));
    if (fmi != 2 && fmi != 3) die("fmi=2 or fmi=3");
    const char *order_name = arg(argc, argv, "order");
    int order = strcmp(order_name, "read-then-step") == 0   ? READ_THEN_STEP
                : strcmp(order_name, "step-then-read") == 0 ? STEP_THEN_READ
                : strcmp(order_name, "jacobi") == 0         ? JACOBI
                                                            : -1;
    if (order < 0) die("unknown order");
    const char *variant = arg(argc, argv, "variant");
    size_t steps = (size_t)strtoull(arg(argc, argv, "steps"), NULL, 10);
    uint64_t h_bits;
    numbers(arg(argc, argv, "step"), &h_bits, 1, 1);
    double h = from_bits(h_bits);

    List nav_in = contract(arg(argc, argv, "nav_gnc"), arg(argc, argv, "nav_sizes"));
    List nav_out = contract(arg(argc, argv, "nav_plant"), arg(argc, argv, "nav_sizes"));
    List cmd_out = contract(arg(argc, argv, "cmd_gnc"), arg(argc, argv, "cmd_sizes"));
    List cmd_in = contract(arg(argc, argv, "cmd_plant"), arg(argc, argv, "cmd_sizes"));
    size_t nlists = strcmp(variant, "reshuffled") == 0 ? ORDERS : 1;
    Lists *lists = calloc(nlists, sizeof *lists);
    if (!lists) die("out of memory");
    for (size_t k = 0; k < nlists; k++) {
        lists[k].nav_in = ordered(&nav_in, variant);
        lists[k].nav_out = ordered(&nav_out, variant);
        lists[k].cmd_out = ordered(&cmd_out, variant);
        lists[k].cmd_in = ordered(&cmd_in, variant);
    }

    double stop = (double)steps * h;
    Unit gnc = load(argc, argv, "gnc", stop);
    Unit plant = load(argc, argv, "plant", stop);
    unsigned int law_vr = (unsigned int)strtoul(arg(argc, argv, "law"), NULL, 10);
    if (fmi == 2) {
        fmi2SetIntegerTYPE *set_integer = (fmi2SetIntegerTYPE *)symbol(
            dlopen(arg(argc, argv, "gnc"), RTLD_NOW | RTLD_LOCAL), "fmi2SetInteger");
        fmi2Integer law = 2;
        check(set_integer(gnc.instance, &law_vr, 1, &law), "fmi2SetInteger (control_law)");
    } else {
        fmi3SetInt32TYPE *set_int32 = (fmi3SetInt32TYPE *)symbol(
            dlopen(arg(argc, argv, "gnc"), RTLD_NOW | RTLD_LOCAL), "fmi3SetInt32");
        fmi3Int32 law = 2;
        check(set_int32(gnc.instance, &law_vr, 1, &law, 1), "fmi3SetInt32 (control_law)");
    }
    initial_reals(argc, argv, &gnc, "gnc_init", "gnc_init_values");
    initial_reals(argc, argv, &plant, "plant_init", "plant_init_values");
    for (int i = 0; i < 2; i++) {
        const Unit *u = i == 0 ? &gnc : &plant;
        void *library = dlopen(arg(argc, argv, i == 0 ? "gnc" : "plant"), RTLD_NOW | RTLD_LOCAL);
        if (fmi == 2) {
            fmi2ExitInitializationModeTYPE *exit_init =
                (fmi2ExitInitializationModeTYPE *)symbol(library, "fmi2ExitInitializationMode");
            check(exit_init(u->instance), "fmi2ExitInitializationMode");
        } else {
            fmi3ExitInitializationModeTYPE *exit_init =
                (fmi3ExitInitializationModeTYPE *)symbol(library, "fmi3ExitInitializationMode");
            check(exit_init(u->instance), "fmi3ExitInitializationMode");
        }
    }

    double nav[MAX_VALUES] = {0}, cmd[MAX_VALUES] = {0};
    int each = strcmp(variant, "per-value") == 0;
    int status = run_loop(&gnc, &plant, lists, nlists, order, each, steps, h, nav, cmd);
    check(status, "a call of the flight");
    printf("bits");
    for (size_t i = 0; i < nav_out.nvalues; i++) {
        uint64_t b;
        memcpy(&b, &nav[i], sizeof b);
        printf(" %016" PRIx64, b);
    }
    printf("\n");
    free(lists);
    return 0;
}
