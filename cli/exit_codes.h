/* Exit statuses of the headplan program (sysexits.h numbering where one fits). */
#ifndef CLI_EXIT_CODES_H
#define CLI_EXIT_CODES_H

enum {
    CLI_EXIT_OK = 0,           /* success; for solve: the correction was reached */
    CLI_EXIT_CLOSEST = 1,      /* solve/batch: only the closest reachable correction */
    CLI_EXIT_UNCOMMANDED = 2,  /* solve: the commanded part was reached, but part of the
                                correction lies in directions the layout cannot observe */
    CLI_EXIT_USAGE = 64,       /* bad command line: unknown option, missing value */
    CLI_EXIT_DATAERR = 65,     /* bad data: a value out of range, a malformed scene */
    CLI_EXIT_NOINPUT = 66,     /* an input file cannot be opened */
    CLI_EXIT_UNAVAILABLE = 69, /* render/plot: gnuplot is not installed (nothing else needs it) */
    CLI_EXIT_SOFTWARE = 70,    /* solver failure or internal error */
    CLI_EXIT_CANTCREAT = 73,   /* an output file cannot be created or is refused (batch -o) */
    CLI_EXIT_IOERR = 74,       /* a write, flush or close of stdout or a file failed */
};

#endif
