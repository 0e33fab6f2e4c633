/* headplan-bench: the benchmark lab beside the product (never installed, never a run-time
 * dependency of the library or of `headplan`). It measures speed against accuracy of every
 * method on the project's scenario catalogue and draws the charts of docs/ with gnuplot.
 * Its standard output is checked like the command line's (exit 74 when it cannot be
 * written). */
#include "bench/bench.h"
#include "cli/cli_output.h"

#include <locale.h>

int main(int argc, char **argv)
{
    setlocale(LC_ALL, "C");
    cli_guard_std_fds();
    return cli_finish_stdout("bench", bench_run_cli(argc, argv));
}
