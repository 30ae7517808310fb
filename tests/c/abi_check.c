/*
 * C ABI conformance check of an FMI 2.0 Co-Simulation shared library, as a C master sees it.
 *
 * Compile-time half: this file includes the official FMI 2.0 headers and then the header
 * that cbindgen generated from our Rust exports (fmi2_exports.h). The official
 * fmi2Functions.h declares every function through its fmi2XxxTYPE typedef, so a Rust
 * signature that differs from the standard's makes the second declaration conflict: a
 * compile error, not a runtime surprise. Built with -std=c99 -Wall -Wextra -Werror -pedantic.
 *
 * Run-time half: dlopen the library, bind all 34 functions through fmi2XxxTYPE pointers,
 * run a short simulation and check statuses, FMU-state round trips (bit-exact
 * continuation), Reset, refusals of bad calls, and what the logger is handed back.
 *
 * Usage: abi_check LIBRARY GUID RESOURCE_URI STEP_SIZE N_STEPS [REAL_OUTPUT_VR...]
 * Prints one line per failed check and a closing "abi_check: N passed, M failed".
 */
#define _POSIX_C_SOURCE 200809L

#include <dlfcn.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "fmi3Functions.h"
#include "fmi2_exports.h"

/* The platform "default" of fmi2TypesPlatform.h, which a Rust FMU must match bit for bit. */
_Static_assert(sizeof(fmi2Real) == 8, "fmi2Real is a 64-bit double");
_Static_assert(sizeof(fmi2Integer) == 4, "fmi2Integer is a 32-bit int");
_Static_assert(sizeof(fmi2Boolean) == 4, "fmi2Boolean is a 32-bit int");
_Static_assert(sizeof(fmi2ValueReference) == 4, "fmi2ValueReference is a 32-bit unsigned int");
_Static_assert(sizeof(fmi2Status) == sizeof(int), "fmi2Status is an int-sized enum");
_Static_assert(sizeof(fmi2CallbackFunctions) == 5 * sizeof(void *),
               "fmi2CallbackFunctions is four function pointers and the environment");

/* The 34 functions of FMI 2.0 Co-Simulation: 25 common, 9 co-simulation. */
#define FMI2_CS_FUNCTIONS(X)                                                                   \
    X(GetTypesPlatform) X(GetVersion) X(SetDebugLogging) X(Instantiate) X(FreeInstance)        \
    X(SetupExperiment) X(EnterInitializationMode) X(ExitInitializationMode) X(Terminate)       \
    X(Reset) X(GetReal) X(GetInteger) X(GetBoolean) X(GetString) X(SetReal) X(SetInteger)      \
    X(SetBoolean) X(SetString) X(GetFMUstate) X(SetFMUstate) X(FreeFMUstate)                   \
    X(SerializedFMUstateSize) X(SerializeFMUstate) X(DeSerializeFMUstate)                      \
    X(GetDirectionalDerivative) X(SetRealInputDerivatives) X(GetRealOutputDerivatives)         \
    X(DoStep) X(CancelStep) X(GetStatus) X(GetRealStatus) X(GetIntegerStatus)                  \
    X(GetBooleanStatus) X(GetStringStatus)

typedef struct {
#define API_FIELD(name) fmi2##name##TYPE *name;
    FMI2_CS_FUNCTIONS(API_FIELD)
#undef API_FIELD
} Fmi2Api;

#define MAX_OUTPUTS 64
#define INSTANCE_NAME "abi_check"

static int passed;
static int failed;

static void check(int ok, const char *what) {
    if (ok) {
        passed++;
    } else {
        failed++;
        printf("FAILED: %s\n", what);
    }
}

/* What the logger saw: every call must hand back our environment and instance name. */
typedef struct {
    int messages;
    int foreign_environment;
    int wrong_instance_name;
} LogRecord;

static LogRecord log_record;

static void logger(fmi2ComponentEnvironment environment, fmi2String instance_name,
                   fmi2Status status, fmi2String category, fmi2String message, ...) {
    log_record.messages++;
    if (environment != (fmi2ComponentEnvironment)&log_record) {
        log_record.foreign_environment++;
    }
    if (instance_name == NULL || strcmp(instance_name, INSTANCE_NAME) != 0) {
        log_record.wrong_instance_name++;
    }
    if (status >= fmi2Warning) {
        va_list args;
        va_start(args, message);
        printf("  [%s] status %d: ", category ? category : "(null)", (int)status);
        vprintf(message, args);
        printf("\n");
        va_end(args);
    }
}

static int load_api(void *library, Fmi2Api *api) {
    int complete = 1;
    /* POSIX guarantees that a data pointer from dlsym converts to a function pointer;
     * C99 does not, so store through the object representation to stay -pedantic clean. */
#define API_LOAD(name)                                                                         \
    *(void **)(&api->name) = dlsym(library, "fmi2" #name);                                     \
    if (api->name == NULL) {                                                                   \
        printf("FAILED: symbol fmi2" #name " not found\n");                                    \
        complete = 0;                                                                          \
    }
    FMI2_CS_FUNCTIONS(API_LOAD)
#undef API_LOAD
    return complete;
}

static int ok_or_warning(fmi2Status status) { return status == fmi2OK || status == fmi2Warning; }

typedef struct {
    const fmi2ValueReference *vr;
    size_t n;
} Outputs;

/* Reads the outputs and checks they are finite; returns 0 on any failure. */
static int read_outputs(const Fmi2Api *api, fmi2Component c, Outputs out, fmi2Real *values) {
    size_t i;
    if (out.n == 0) {
        return 1;
    }
    if (!ok_or_warning(api->GetReal(c, out.vr, out.n, values))) {
        return 0;
    }
    for (i = 0; i < out.n; i++) {
        if (!isfinite(values[i])) {
            return 0;
        }
    }
    return 1;
}

/* Steps from step index `first` to `last` (t = i * h, as a master with an integer step
 * counter does) and leaves the outputs after the last step in `values`. */
static int run_steps(const Fmi2Api *api, fmi2Component c, fmi2Real h, int first, int last,
                     Outputs out, fmi2Real *values) {
    int i;
    for (i = first; i < last; i++) {
        if (!ok_or_warning(api->DoStep(c, i * h, h, fmi2True))) {
            printf("  fmi2DoStep at step %d failed\n", i);
            return 0;
        }
        if (!read_outputs(api, c, out, values)) {
            printf("  outputs after step %d are not readable or not finite\n", i);
            return 0;
        }
    }
    return 1;
}

static int same_bits(const fmi2Real *a, const fmi2Real *b, size_t n) {
    return n == 0 || memcmp(a, b, n * sizeof(fmi2Real)) == 0;
}

static fmi2Component instantiate(const Fmi2Api *api, const fmi2CallbackFunctions *callbacks,
                                 fmi2Type type, const char *guid, const char *resources) {
    return api->Instantiate(INSTANCE_NAME, type, guid, resources, callbacks, fmi2False,
                            fmi2False);
}

static int initialize(const Fmi2Api *api, fmi2Component c) {
    return ok_or_warning(api->SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0)) &&
           ok_or_warning(api->EnterInitializationMode(c)) &&
           ok_or_warning(api->ExitInitializationMode(c));
}

static void check_states(const Fmi2Api *api, fmi2Component c, fmi2Real h, int from, int to,
                         Outputs out) {
    fmi2Real reference[MAX_OUTPUTS], again[MAX_OUTPUTS];
    fmi2FMUstate saved = NULL, restored = NULL, refused = NULL;
    size_t size = 0;
    fmi2Byte *bytes;

    check(api->GetFMUstate(c, &saved) == fmi2OK && saved != NULL, "fmi2GetFMUstate");
    check(run_steps(api, c, h, from, to, out, reference), "steps after fmi2GetFMUstate");
    check(api->SetFMUstate(c, saved) == fmi2OK, "fmi2SetFMUstate");
    check(run_steps(api, c, h, from, to, out, again), "steps after fmi2SetFMUstate");
    check(same_bits(reference, again, out.n), "restored state continues bit for bit");

    check(api->SerializedFMUstateSize(c, saved, &size) == fmi2OK && size > 0,
          "fmi2SerializedFMUstateSize");
    bytes = size > 0 ? malloc(size) : NULL;
    if (bytes == NULL) {
        check(0, "a serialization buffer of the announced size");
        return;
    }
    check(api->SerializeFMUstate(c, saved, bytes, size) == fmi2OK, "fmi2SerializeFMUstate");
    check(api->DeSerializeFMUstate(c, bytes, size, &restored) == fmi2OK && restored != NULL,
          "fmi2DeSerializeFMUstate");
    check(api->SetFMUstate(c, restored) == fmi2OK, "fmi2SetFMUstate of a deserialized state");
    check(run_steps(api, c, h, from, to, out, again), "steps after deserialization");
    check(same_bits(reference, again, out.n), "deserialized state continues bit for bit");

    check(api->DeSerializeFMUstate(c, bytes, size - 1, &refused) == fmi2Error,
          "a truncated serialized state is refused");
    memset(bytes, 0xA5, size);
    check(api->DeSerializeFMUstate(c, bytes, size, &refused) == fmi2Error,
          "a foreign serialized state is refused");
    check(refused == NULL, "a refused state is not handed out");
    free(bytes);

    check(api->FreeFMUstate(c, &saved) == fmi2OK && saved == NULL, "fmi2FreeFMUstate");
    check(api->FreeFMUstate(c, &restored) == fmi2OK && restored == NULL,
          "fmi2FreeFMUstate of a deserialized state");
}

/* Bad calls are refused with fmi2Error (or fmi2Discard where the standard says so) and,
 * as the export layer documents, leave the instance as it was. */
static void check_refusals(const Fmi2Api *api, fmi2Component c, fmi2Real t, fmi2Real h) {
    const fmi2ValueReference unknown_vr = 0x7FFFFFF0u;
    fmi2Real real = 0.0;
    fmi2Integer integer = 0;
    fmi2Boolean boolean = fmi2True;
    fmi2String string = NULL;
    fmi2Status status = fmi2OK;
    int before = log_record.messages;

    check(api->DoStep(c, t, 0.0, fmi2True) == fmi2Error, "fmi2DoStep with h = 0 is refused");
    check(api->DoStep(c, t, -h, fmi2True) == fmi2Error, "fmi2DoStep with h < 0 is refused");
    check(api->DoStep(c, t + 10.0 * h, h, fmi2True) == fmi2Error,
          "fmi2DoStep at a communication point that is not the current time is refused");
    check(api->DoStep(NULL, t, h, fmi2True) == fmi2Error, "fmi2DoStep on NULL is refused");
    check(api->GetReal(c, &unknown_vr, 1, &real) == fmi2Error,
          "fmi2GetReal of an unknown value reference is refused");
    check(api->GetReal(c, NULL, 1, &real) == fmi2Error,
          "fmi2GetReal with a NULL array and nvr > 0 is refused");
    check(api->CancelStep(c) == fmi2Error, "fmi2CancelStep without an asynchronous step");
    {
        /* Set by the test from the description's providesDirectionalDerivative. */
        const char *provides = getenv("ABI_CHECK_PROVIDES_DIRECTIONAL_DERIVATIVE");
        if (provides != NULL && provides[0] == '1') {
            check(api->GetDirectionalDerivative(c, NULL, 0, NULL, 0, NULL, NULL) == fmi2OK,
                  "fmi2GetDirectionalDerivative of nothing is answered (it is provided)");
            check(api->GetDirectionalDerivative(c, &unknown_vr, 1, &unknown_vr, 1, &real,
                                                &real) == fmi2Error,
                  "fmi2GetDirectionalDerivative of an unknown value reference is refused");
        } else {
            check(api->GetDirectionalDerivative(c, NULL, 0, NULL, 0, NULL, NULL) == fmi2Error,
                  "fmi2GetDirectionalDerivative is not provided");
        }
    }
    check(api->SetRealInputDerivatives(c, NULL, 0, NULL, NULL) == fmi2Error,
          "fmi2SetRealInputDerivatives is not supported");
    check(api->GetRealOutputDerivatives(c, NULL, 0, NULL, NULL) == fmi2Error,
          "fmi2GetRealOutputDerivatives is not supported");
    check(api->GetStatus(c, fmi2DoStepStatus, &status) == fmi2Discard,
          "fmi2GetStatus(fmi2DoStepStatus) is not available");
    check(api->GetIntegerStatus(c, fmi2DoStepStatus, &integer) == fmi2Discard,
          "fmi2GetIntegerStatus is not available");
    check(api->GetStringStatus(c, fmi2PendingStatus, &string) == fmi2Discard,
          "fmi2GetStringStatus(fmi2PendingStatus) is not available");
    check(log_record.messages > before, "refusals are logged");

    /* The FMU accumulates t + h, we compute i * h: equal up to rounding. */
    check(api->GetRealStatus(c, fmi2LastSuccessfulTime, &real) == fmi2OK &&
              fabs(real - t) <= 1e-9 * (fabs(t) > 1.0 ? fabs(t) : 1.0),
          "fmi2GetRealStatus(fmi2LastSuccessfulTime) is the current time");
    check(api->GetBooleanStatus(c, fmi2Terminated, &boolean) == fmi2OK && boolean == fmi2False,
          "fmi2GetBooleanStatus(fmi2Terminated) is false while running");
    check(ok_or_warning(api->DoStep(c, t, h, fmi2True)), "a good step after the refusals");
}

/* Every get/set function accepts an empty request (nvr = 0 with NULL arrays). */
static void check_empty_requests(const Fmi2Api *api, fmi2Component c) {
    check(api->GetReal(c, NULL, 0, NULL) == fmi2OK, "fmi2GetReal with nvr = 0");
    check(api->GetInteger(c, NULL, 0, NULL) == fmi2OK, "fmi2GetInteger with nvr = 0");
    check(api->GetBoolean(c, NULL, 0, NULL) == fmi2OK, "fmi2GetBoolean with nvr = 0");
    check(api->GetString(c, NULL, 0, NULL) == fmi2OK, "fmi2GetString with nvr = 0");
    check(api->SetReal(c, NULL, 0, NULL) == fmi2OK, "fmi2SetReal with nvr = 0");
    check(api->SetInteger(c, NULL, 0, NULL) == fmi2OK, "fmi2SetInteger with nvr = 0");
    check(api->SetBoolean(c, NULL, 0, NULL) == fmi2OK, "fmi2SetBoolean with nvr = 0");
    check(api->SetString(c, NULL, 0, NULL) == fmi2OK, "fmi2SetString with nvr = 0");
}

int main(int argc, char **argv) {
    Fmi2Api api;
    void *library;
    fmi2CallbackFunctions callbacks;
    fmi2Component c;
    fmi2ValueReference vr[MAX_OUTPUTS];
    fmi2Real first_step[MAX_OUTPUTS], values[MAX_OUTPUTS];
    Outputs out;
    const char *guid, *resources;
    fmi2Real h;
    int n_steps, i;

    if (argc < 6 || argc - 6 > MAX_OUTPUTS) {
        fprintf(stderr, "usage: %s LIBRARY GUID RESOURCE_URI STEP_SIZE N_STEPS [VR...]\n",
                argv[0]);
        return 2;
    }
    guid = argv[2];
    resources = argv[3];
    h = strtod(argv[4], NULL);
    n_steps = atoi(argv[5]);
    for (i = 6; i < argc; i++) {
        vr[i - 6] = (fmi2ValueReference)strtoul(argv[i], NULL, 10);
    }
    out.vr = vr;
    out.n = (size_t)(argc - 6);
    if (!(h > 0.0) || n_steps < 4) {
        fprintf(stderr, "STEP_SIZE must be > 0 and N_STEPS >= 4\n");
        return 2;
    }

    library = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (library == NULL) {
        printf("FAILED: dlopen: %s\n", dlerror());
        return 1;
    }
    check(load_api(library, &api), "all 34 functions resolve");
    if (failed) {
        return 1;
    }

    check(strcmp(api.GetTypesPlatform(), fmi2TypesPlatform) == 0, "fmi2GetTypesPlatform");
    check(strcmp(api.GetVersion(), fmi2Version) == 0, "fmi2GetVersion");

    callbacks.logger = logger;
    callbacks.allocateMemory = calloc;
    callbacks.freeMemory = free;
    callbacks.stepFinished = NULL;
    callbacks.componentEnvironment = &log_record;

    check(instantiate(&api, &callbacks, fmi2CoSimulation, "{not-the-guid}", resources) == NULL,
          "fmi2Instantiate with a wrong GUID returns NULL");
    /* Model Exchange: instantiable exactly when the library exports its functions. */
    if (dlsym(library, "fmi2SetContinuousStates") != NULL) {
        fmi2Component me = instantiate(&api, &callbacks, fmi2ModelExchange, guid, resources);
        check(me != NULL, "fmi2Instantiate for Model Exchange (its functions are exported)");
        if (me != NULL) {
            api.FreeInstance(me);
        }
        check(log_record.messages >= 1, "the refused instantiation is logged");
    } else {
        check(instantiate(&api, &callbacks, fmi2ModelExchange, guid, resources) == NULL,
              "fmi2Instantiate for Model Exchange returns NULL");
        check(log_record.messages >= 2, "refused instantiations are logged");
    }

    c = instantiate(&api, &callbacks, fmi2CoSimulation, guid, resources);
    check(c != NULL, "fmi2Instantiate");
    if (c == NULL) {
        printf("abi_check: %d passed, %d failed\n", passed, failed);
        return 1;
    }
    check(api.SetDebugLogging(c, fmi2True, 0, NULL) == fmi2OK, "fmi2SetDebugLogging (all)");
    check(initialize(&api, c), "setup and initialization");
    check(read_outputs(&api, c, out, values), "outputs after initialization are finite");
    check_empty_requests(&api, c);

    check(run_steps(&api, c, h, 0, 1, out, first_step), "first step");
    check(run_steps(&api, c, h, 1, n_steps / 2, out, values), "steps to the middle");
    check_states(&api, c, h, n_steps / 2, n_steps, out);
    check_refusals(&api, c, n_steps * h, h);

    check(api.Reset(c) == fmi2OK, "fmi2Reset");
    check(initialize(&api, c), "initialization after fmi2Reset");
    check(run_steps(&api, c, h, 0, 1, out, values), "first step after fmi2Reset");
    check(same_bits(first_step, values, out.n), "fmi2Reset gives a fresh instance");
    check(api.Terminate(c) == fmi2OK, "fmi2Terminate");
    api.FreeInstance(c);
    api.FreeInstance(NULL);

    check(log_record.foreign_environment == 0,
          "the logger always gets our componentEnvironment back");
    check(log_record.wrong_instance_name == 0, "the logger always gets the instance name");

    dlclose(library);
    printf("abi_check: %d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}
