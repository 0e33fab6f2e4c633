/* headplan-bench: the benchmark lab beside the product (never installed, never a run-time
 * dependency of the library or of `headplan`). It measures speed against accuracy of every
 * method on the project's scenario catalogue and draws the charts of docs/ with gnuplot. */
#include "bench/bench.h"

#include <locale.h>

int main(int argc, char **argv)
{
    setlocale(LC_ALL, "C");
    return bench_run_cli(argc, argv);
}
