# Debian packages (CPack DEB), one per install component:
#   libheadplan0      the shared library (lib)
#   libheadplan-dev   headers, static library, CMake package, pkg-config file (dev)
#   headplan          the command-line program, its man pages, scenes, examples, docs (cli)
#   python3-headplan  the Python module (python)
# `cpack -G DEB --config build/CPackConfig.cmake` (from the build folder) writes them; the
# package test (tests/package/) installs them into a clean Debian 12. Run-time dependencies
# come from the binaries themselves (dpkg-shlibdeps); what a binary cannot say (the -dev
# package's build dependencies, Python and NumPy) is stated here.
set(CPACK_PACKAGE_NAME headplan)
set(CPACK_PACKAGE_VENDOR "headplan")
set(CPACK_PACKAGE_CONTACT "headplan maintainers <headplan@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_RESOURCE_FILE_LICENSE ${CMAKE_CURRENT_SOURCE_DIR}/LICENSE)
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_COMPONENTS_ALL lib dev cli)
if(TARGET headplan_python)
  list(APPEND CPACK_COMPONENTS_ALL python)
endif()
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_ENABLE_COMPONENT_DEPENDS ON)  # dev -> libheadplan0 (= version)

set(CPACK_DEBIAN_LIB_PACKAGE_NAME libheadplan0)
set(CPACK_DEBIAN_LIB_PACKAGE_SECTION libs)
set(CPACK_DEBIAN_LIB_PACKAGE_GENERATE_SHLIBS ON)  # a shlibs file and the ldconfig trigger
set(CPACK_COMPONENT_LIB_DESCRIPTION "headplan: ${PROJECT_DESCRIPTION} (shared library)")

set(CPACK_DEBIAN_DEV_PACKAGE_NAME libheadplan-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_COMPONENT_DEV_DEPENDS lib)
# headplan.pc's Requires.private and headplanConfig.cmake's find_dependency name these; the
# static library needs them to link.
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS
    "pkg-config, coinor-libipopt-dev, libnlopt-dev, libyaml-dev, libjansson-dev")
set(CPACK_COMPONENT_DEV_DESCRIPTION "headplan: development files (headers, static library, CMake package, pkg-config)")

set(CPACK_DEBIAN_CLI_PACKAGE_NAME headplan)
set(CPACK_DEBIAN_CLI_PACKAGE_SUGGESTS "gnuplot-nox")  # render and plot only
set(CPACK_COMPONENT_CLI_DESCRIPTION "headplan: the command-line program, man pages, example scenes and documentation")

set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-headplan)
set(CPACK_DEBIAN_PYTHON_PACKAGE_SECTION python)
if(Python3_VERSION)  # the module is built for one Python minor version
  math(EXPR _next "${Python3_VERSION_MINOR} + 1")
  set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS
      "python3 (>= ${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}), python3 (<< ${Python3_VERSION_MAJOR}.${_next}), python3-numpy")
endif()
set(CPACK_COMPONENT_PYTHON_DESCRIPTION "headplan: the Python module")
include(CPack)
