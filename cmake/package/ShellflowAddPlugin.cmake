# shellflow_add_plugin(<name> SOURCES <files...> [LIBRARIES <targets...>])
#
# The installed twin of cmake/ShellflowPlugin.cmake, for plugins built out of tree against
# find_package(shellflow). Builds the module library shellflow_<name>.so into
# SHELLFLOW_PLUGIN_OUTPUT_DIR (default: <build>/plugins; point a scene's "plugin_path" or
# SHELLFLOW_PLUGIN_PATH at it) and installs it under lib/shellflow/plugins. <name> must be
# the name given to the registration macro (SHELLFLOW_SOLID_PLUGIN and friends): the loader
# checks. The loader also checks the build signature: build with the compiler, standard
# library and Eigen that built shellflow.
function(shellflow_add_plugin name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBRARIES" ${ARGN})
  if(NOT name MATCHES "^[a-z][a-z0-9_]*$")
    message(FATAL_ERROR "shellflow_add_plugin: '${name}' is not a plugin name; use lower-case "
                        "letters, digits and '_', starting with a letter (as my_cloth)")
  endif()
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "shellflow_add_plugin(${name}): no SOURCES given")
  endif()
  if(NOT SHELLFLOW_PLUGIN_OUTPUT_DIR)
    set(SHELLFLOW_PLUGIN_OUTPUT_DIR ${CMAKE_BINARY_DIR}/plugins)
  endif()
  set(target shellflow_plugin_${name})
  add_library(${target} MODULE ${ARG_SOURCES})
  add_library(shellflow::plugin_${name} ALIAS ${target})
  target_compile_features(${target} PRIVATE cxx_std_20)
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  target_link_libraries(${target} PRIVATE shellflow::sdk ${ARG_LIBRARIES})
  set_target_properties(${target} PROPERTIES
    PREFIX ""
    OUTPUT_NAME shellflow_${name}
    LIBRARY_OUTPUT_DIRECTORY ${SHELLFLOW_PLUGIN_OUTPUT_DIR}
    CXX_EXTENSIONS OFF
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  install(TARGETS ${target} LIBRARY DESTINATION lib/shellflow/plugins)
endfunction()
