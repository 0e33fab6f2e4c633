/* libFuzzer target: the trace reader (CSV and JSON Lines) on arbitrary bytes. The first byte
 * picks the format; every row is read to the end. Any crash, leak or sanitizer report is a
 * finding; error returns are the expected outcome for most inputs. */
#include "headplan/hp_trace.h"

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0) return 0;
    hp_trace_format fmt = (data[0] & 1) ? HP_TRACE_JSONL : HP_TRACE_CSV;
    /* Bits 1-2: the caller states nothing, deviation or correction (a trace that states
     * nothing itself is then still read). */
    hp_trace_rows rows = (data[0] & 2) ? HP_TRACE_DEVIATION : HP_TRACE_CORRECTION;
    const hp_trace_rows *given = (data[0] & 4) ? NULL : &rows;
    hp_trace_reader *r = NULL;
    hp_diag d;
    if (hp_trace_open_mem((const char *)data + 1, size - 1, "fuzz", fmt, given, &r, &d) != HP_OK)
        return 0;
    hp_trace_row row;
    for (int i = 0; i < 100000; ++i) {
        hp_error e = hp_trace_next(r, &row, &d);
        if (e == HP_END || e == HP_ERR_STATE || e == HP_ERR_IO) break;
    }
    hp_trace_close(r);
    return 0;
}
