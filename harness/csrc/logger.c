/*
 * The C side of the FMI 2.0 callbacks the harness hands to an FMU.
 *
 * fmi2CallbackLogger is variadic and stable Rust cannot define a variadic function, so this
 * shim formats the message with vsnprintf and passes the finished text to a plain Rust
 * function. The Rust function is not a global symbol: componentEnvironment points to a
 * harness_log_env whose first member is that function, so no global state is needed and
 * each instance's messages reach its own sink.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

/* Mirrors `LogEnv` in src/loader/logger.rs (#[repr(C)], forward function first). */
typedef struct harness_log_env {
    void (*forward)(const struct harness_log_env *env, const char *instance_name, int status,
                    const char *category, const char *message);
} harness_log_env;

/* Messages up to this size are formatted on the stack; longer ones go to the heap. */
enum { HARNESS_STACK_MESSAGE_BYTES = 1024 };

void harness_fmi2_logger(void *component_environment, const char *instance_name, int status,
                         const char *category, const char *message, ...) {
    const harness_log_env *env = (const harness_log_env *)component_environment;
    char stack_buffer[HARNESS_STACK_MESSAGE_BYTES];
    char *text = stack_buffer;
    va_list args;
    int needed;

    if (env == NULL || env->forward == NULL) {
        return;
    }
    if (message == NULL) {
        env->forward(env, instance_name, status, category, "");
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
void *harness_fmi2_allocate_memory(size_t n_objects, size_t size) {
    return calloc(n_objects, size);
}

void harness_fmi2_free_memory(void *object) {
    free(object);
}
