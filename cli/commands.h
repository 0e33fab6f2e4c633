/* The subcommands of the headplan program. Each takes argc/argv after the subcommand name
 * and returns the process exit status (see cli/exit_codes.h). */
#ifndef HP_CLI_COMMANDS_H
#define HP_CLI_COMMANDS_H

int hp_cmd_ik(int argc, char **argv);
int hp_cmd_fk(int argc, char **argv);
int hp_cmd_paper(int argc, char **argv);
int hp_cmd_solve(int argc, char **argv);
int hp_cmd_analyze(int argc, char **argv);
int hp_cmd_batch(int argc, char **argv);
int hp_cmd_fit(int argc, char **argv);
int hp_cmd_horizon(int argc, char **argv);
int hp_cmd_render(int argc, char **argv);
int hp_cmd_plot(int argc, char **argv);

#endif
