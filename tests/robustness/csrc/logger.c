/*
 * The FMI 2.0 logger the robustness tests hand to an FMU.
 *
 * fmi2CallbackLogger is variadic, which stable Rust cannot define. This shim formats the
 * message with vsnprintf exactly as a C master would (so a format string that does not
 * match its arguments would show up, under valgrind, as a read of garbage) and passes the
 * finished text to the Rust recorder reached through componentEnvironment: no global state.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

/* Mirrors `LogSink` in src/logger.rs (#[repr(C)], forward function first). */
typedef struct robust_log_sink {
    void (*forward)(const struct robust_log_sink *sink, const char *instance_name, int status,
                    const char *category, const char *message);
} robust_log_sink;

void robust_fmi2_logger(void *component_environment, const char *instance_name, int status,
                        const char *category, const char *message, ...) {
    const robust_log_sink *sink = (const robust_log_sink *)component_environment;
    char stack_text[512];
    char *text = stack_text;
    va_list args;
    int needed;

    if (sink == NULL || sink->forward == NULL) {
        return;
    }
    if (message == NULL) {
        sink->forward(sink, instance_name, status, category, NULL);
        return;
    }
    va_start(args, message);
    needed = vsnprintf(stack_text, sizeof stack_text, message, args);
    va_end(args);
    if (needed < 0) {
        sink->forward(sink, instance_name, status, category, message);
        return;
    }
    if ((size_t)needed >= sizeof stack_text) {
        char *heap_text = (char *)malloc((size_t)needed + 1u);
        if (heap_text != NULL) {
            va_start(args, message);
            vsnprintf(heap_text, (size_t)needed + 1u, message, args);
            va_end(args);
            text = heap_text;
        }
    }
    sink->forward(sink, instance_name, status, category, text);
    if (text != stack_text) {
        free(text);
    }
}
