/*
 * The C side of the FMI 2.0 callbacks a master hands to an FMU (the harness loader and the
 * test crates; never linked into an FMU).
 *
 * fmi2CallbackLogger is variadic and stable Rust cannot define a variadic function, so this
 * shim formats the message with vsnprintf exactly as a C master would (a format string that
 * does not match its arguments shows up, under valgrind, as a read of garbage) and passes the
 * finished text to a plain Rust function. That function is not a global symbol:
 * componentEnvironment points to a struct whose first member is an fmi_abi_log_sink, so no
 * global state is needed and each instance's messages reach its own sink.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

/* Mirrors `LogSink` in src/callbacks.rs (#[repr(C)], forward function first). */
typedef struct fmi_abi_log_sink {
    void (*forward)(const struct fmi_abi_log_sink *sink, const char *instance_name, int status,
                    const char *category, const char *message);
} fmi_abi_log_sink;

/* Messages up to this size are formatted on the stack; longer ones go to the heap. */
enum { FMI_ABI_STACK_MESSAGE_BYTES = 1024 };

void fmi_abi_fmi2_logger(void *component_environment, const char *instance_name, int status,
                         const char *category, const char *message, ...) {
    const fmi_abi_log_sink *env = (const fmi_abi_log_sink *)component_environment;
    char stack_buffer[FMI_ABI_STACK_MESSAGE_BYTES];
    char *text = stack_buffer;
    va_list args;
    int needed;

    if (env == NULL || env->forward == NULL) {
        return;
    }
    if (message == NULL) {
        /* Passed on as NULL: a test may want to see that an FMU logged no text at all. */
        env->forward(env, instance_name, status, category, NULL);
        return;
    }

    va_start(args, message);
    needed = vsnprintf(stack_buffer, sizeof stack_buffer, message, args);
    va_end(args);

    if (needed < 0) {
        /* An encoding error in the FMU's format: keep the raw format string rather than lose it. */
        env->forward(env, instance_name, status, category, message);
        return;
    }
    if ((size_t)needed >= sizeof stack_buffer) {
        char *heap_buffer = (char *)malloc((size_t)needed + 1u);
        if (heap_buffer != NULL) {
            va_start(args, message);
            vsnprintf(heap_buffer, (size_t)needed + 1u, message, args);
            va_end(args);
            text = heap_buffer;
        }
        /* Without memory the truncated stack copy is still worth delivering. */
    }
    env->forward(env, instance_name, status, category, text);
    if (text != stack_buffer) {
        free(text);
    }
}

/* FMI 2.0 requires allocateMemory with calloc semantics and a matching freeMemory. */
void *fmi_abi_fmi2_allocate_memory(size_t n_objects, size_t size) {
    return calloc(n_objects, size);
}

void fmi_abi_fmi2_free_memory(void *object) {
    free(object);
}
