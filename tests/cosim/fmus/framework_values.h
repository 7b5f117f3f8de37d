#ifndef ROBOGEN_TEST_FRAMEWORK_VALUES_H
#define ROBOGEN_TEST_FRAMEWORK_VALUES_H
/* The storage of String and Binary variables in a test FMU's Model (see framework_types.h). */
#include <stddef.h>
#include <stdint.h>

#define TEXT_SIZE 64  /* a String's bytes, its terminating NUL included */
#define BYTES_SIZE 32 /* a Binary's bytes at most */
typedef char Text[TEXT_SIZE];
typedef struct {
    size_t size;
    uint8_t data[BYTES_SIZE];
} Bytes;

#endif
