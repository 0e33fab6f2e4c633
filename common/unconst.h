/* Internal: a const pointer handed to an outside interface whose prototype lacks the const
 * but which only reads through it (Ipopt's C interface and callbacks, execv's argv), or to a
 * function that writes into an object the caller owns and that is never defined const.
 * The one place a qualifier is dropped: through a union, so that -Wcast-qual keeps flagging
 * every plain cast that would hide a write into a const object. Not installed. */
#ifndef HP_COMMON_UNCONST_H
#define HP_COMMON_UNCONST_H

static inline void *hpi_unconst(const void *p)
{
    union {
        const void *c;
        void *m;
    } u = {p};
    return u.m;
}

#endif
