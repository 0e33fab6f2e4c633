# Man pages for `headplan` and each subcommand, generated from --help at build time
# (cmake/man_pages.sh, help2man) and installed to share/man/man1 (component cli). Built from
# the build tree's program, whose help names the source tree's folders ("docs",
# "scenarios"); the install step (cmake/install_man.cmake) writes the installed folders in
# their place, for the prefix being installed to.
find_program(HP_HELP2MAN help2man)
if(HP_HELP2MAN)
  set(HP_MAN_DIR ${CMAKE_CURRENT_BINARY_DIR}/man)
  add_custom_command(OUTPUT ${HP_MAN_DIR}/man1/headplan.1
    COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cmake/man_pages.sh $<TARGET_FILE:headplan_cli>
            ${HP_MAN_DIR} ${PROJECT_VERSION}
    DEPENDS headplan_cli ${CMAKE_CURRENT_SOURCE_DIR}/cmake/man_pages.sh
    COMMENT "Man pages from --help (help2man)" VERBATIM)
  add_custom_target(headplan_man ALL DEPENDS ${HP_MAN_DIR}/man1/headplan.1)
  install(CODE "set(HP_MAN_DIR \"${HP_MAN_DIR}\")
set(HP_MAN_DOCS \"${CMAKE_INSTALL_DATADIR}/doc/headplan/docs\")
set(HP_MAN_SCENES \"${CMAKE_INSTALL_DATADIR}/headplan/scenarios\")
set(HP_MAN_DEST \"${CMAKE_INSTALL_MANDIR}/man1\")" COMPONENT cli)
  install(SCRIPT ${CMAKE_CURRENT_SOURCE_DIR}/cmake/install_man.cmake COMPONENT cli)
else()
  message(STATUS "headplan: no man pages (help2man not found; scripts/install-deps.sh installs it)")
endif()
