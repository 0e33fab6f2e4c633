/* The subcommands of the headplan program. Each takes argc/argv after the subcommand name
 * and returns the process exit status (see cli/exit_codes.h). */
#ifndef CLI_COMMANDS_H
#define CLI_COMMANDS_H

int cmd_ik(int argc, char **argv);
int cmd_fk(int argc, char **argv);
int cmd_paper(int argc, char **argv);
int cmd_solve(int argc, char **argv);
int cmd_analyze(int argc, char **argv);
int cmd_batch(int argc, char **argv);
int cmd_fit(int argc, char **argv);
int cmd_horizon(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_plot(int argc, char **argv);

#endif
