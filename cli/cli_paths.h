/* Where --help sends the reader: the documentation and the example scenes installed beside
 * this program, or the source tree's folders when it runs from a build tree. */
#ifndef CLI_PATHS_H
#define CLI_PATHS_H

/* PREFIX/share/doc/headplan/docs when this program is PREFIX/bin/headplan and that folder
 * holds the documentation (an install, `cmake --install` or the Debian package), else
 * "docs", the folder as seen from the top of a checkout. Never NULL. */
const char *cli_doc_dir(void);

/* PREFIX/share/headplan/scenarios when installed the same way, else "scenarios". */
const char *cli_scene_dir(void);

#endif
