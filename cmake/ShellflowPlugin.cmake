# shellflow_add_plugin(<name> SOURCES <files...> [LIBRARIES <targets...>])
#
# Builds the plugin <name> as the module library `shellflow_<name>.so` in the
# build tree's plugin folder (where the loader searches) and installs it under
# lib/shellflow/plugins. The file name must match the name given to the
# registration macro (SHELLFLOW_SOLID_PLUGIN and friends): the loader checks.
function(shellflow_add_plugin name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBRARIES" ${ARGN})
  set(target shellflow_plugin_${name})
  add_library(${target} MODULE ${ARG_SOURCES})
  add_library(shellflow::plugin_${name} ALIAS ${target})
  shellflow_target_defaults(${target})
  target_link_libraries(${target} PRIVATE shellflow::shellflow ${ARG_LIBRARIES})
  set_target_properties(${target} PROPERTIES
    PREFIX ""
    OUTPUT_NAME shellflow_${name}
    LIBRARY_OUTPUT_DIRECTORY ${SHELLFLOW_PLUGIN_OUTPUT_DIR}
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  install(TARGETS ${target} LIBRARY DESTINATION ${SHELLFLOW_PLUGIN_INSTALL_DIR})
  # Lets the shellflow executable depend on every plugin, so `cmake --build`
  # of the harness alone still yields a runnable tree.
  set_property(GLOBAL APPEND PROPERTY SHELLFLOW_PLUGIN_TARGETS ${target})
endfunction()
