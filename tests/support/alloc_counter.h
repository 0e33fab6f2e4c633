/* Counting heap allocations in a test executable linked with
 *   -Wl,--wrap=malloc,--wrap=calloc,--wrap=realloc,--wrap=free,--wrap=aligned_alloc,
 *   --wrap=posix_memalign,--wrap=_Znwm,--wrap=_Znam
 * (see tests/CMakeLists.txt). While alloc_armed is 1, every allocation and every free of a
 * non-NULL pointer adds one to alloc_count. Include in exactly one file of the test. */
#ifndef HP_TEST_ALLOC_COUNTER_H
#define HP_TEST_ALLOC_COUNTER_H

#include <stddef.h>

static int alloc_armed;
static long alloc_count;

void *__real_malloc(size_t n);
void *__real_calloc(size_t a, size_t b);
void *__real_realloc(void *p, size_t n);
void __real_free(void *p);
void *__real_aligned_alloc(size_t a, size_t n);
int __real_posix_memalign(void **p, size_t a, size_t n);
void *__real__Znwm(size_t n);
void *__real__Znam(size_t n);

void *__wrap_malloc(size_t n);
void *__wrap_calloc(size_t a, size_t b);
void *__wrap_realloc(void *p, size_t n);
void __wrap_free(void *p);
void *__wrap_aligned_alloc(size_t a, size_t n);
int __wrap_posix_memalign(void **p, size_t a, size_t n);
void *__wrap__Znwm(size_t n);
void *__wrap__Znam(size_t n);

void *__wrap_malloc(size_t n)
{
    alloc_count += alloc_armed;
    return __real_malloc(n);
}
void *__wrap_calloc(size_t a, size_t b)
{
    alloc_count += alloc_armed;
    return __real_calloc(a, b);
}
void *__wrap_realloc(void *p, size_t n)
{
    alloc_count += alloc_armed;
    return __real_realloc(p, n);
}
void __wrap_free(void *p)
{
    alloc_count += alloc_armed && p;
    __real_free(p);
}
void *__wrap_aligned_alloc(size_t a, size_t n)
{
    alloc_count += alloc_armed;
    return __real_aligned_alloc(a, n);
}
int __wrap_posix_memalign(void **p, size_t a, size_t n)
{
    alloc_count += alloc_armed;
    return __real_posix_memalign(p, a, n);
}
void *__wrap__Znwm(size_t n)
{
    alloc_count += alloc_armed;
    return __real__Znwm(n);
}
void *__wrap__Znam(size_t n)
{
    alloc_count += alloc_armed;
    return __real__Znam(n);
}

#endif
