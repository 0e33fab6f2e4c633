# Install step of the man pages (cmake/man.cmake): the pages from the build tree's --help
# name the source tree's folders; the installed pages name the installed ones under the
# prefix being installed to (CMAKE_INSTALL_PREFIX here is `--prefix` or the package's /usr).
# The help prints them as "documentation: docs", "example scenes: scenarios" and
# "(scenarios)" (cli/cli_paths.c's fallbacks). Installed gzipped, as Debian policy asks
# (gzip -9n: no name or time stamp inside, so two installs give the same bytes).
file(GLOB _pages "${HP_MAN_DIR}/man1/*.1")
if(NOT _pages)
  message(FATAL_ERROR "no man pages in ${HP_MAN_DIR}/man1: build first")
endif()
set(_docs "${CMAKE_INSTALL_PREFIX}/${HP_MAN_DOCS}")
set(_scenes "${CMAKE_INSTALL_PREFIX}/${HP_MAN_SCENES}")
# A folder of this install's own: installs (tests, cpack) may run at the same time.
string(RANDOM LENGTH 12 _r)
set(_out "${HP_MAN_DIR}/installing-${_r}")
file(MAKE_DIRECTORY "${_out}")
foreach(_p ${_pages})
  file(READ "${_p}" _t)
  string(REGEX REPLACE "documentation: docs" "documentation: ${_docs}" _t "${_t}")
  string(REGEX REPLACE "example scenes: scenarios" "example scenes: ${_scenes}" _t "${_t}")
  string(REPLACE "(scenarios)" "(${_scenes})" _t "${_t}")
  get_filename_component(_n "${_p}" NAME)
  file(WRITE "${_out}/${_n}" "${_t}")
  execute_process(COMMAND gzip -9nf "${_out}/${_n}" RESULT_VARIABLE _rc)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "gzip ${_out}/${_n} failed (${_rc})")
  endif()
endforeach()
file(GLOB _installed "${_out}/*.1.gz")
file(INSTALL ${_installed} DESTINATION "${CMAKE_INSTALL_PREFIX}/${HP_MAN_DEST}")
file(REMOVE_RECURSE "${_out}")
