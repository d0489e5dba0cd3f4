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

# shellflow_add_plugin_core(<name> SOURCES <files...> [PUBLIC <targets...>] [PRIVATE <targets...>])
#
# The static library `shellflow_<name>_core` (alias shellflow::<name>_core) holding a
# plugin's physics or format code, so that both the plugin module and its tests link it.
# Its include/ folder is public; it links libshellflow publicly.
function(shellflow_add_plugin_core name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC;PRIVATE" ${ARGN})
  set(target shellflow_${name}_core)
  add_library(${target} STATIC ${ARG_SOURCES})
  add_library(shellflow::${name}_core ALIAS ${target})
  shellflow_target_defaults(${target})
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/include)
    target_include_directories(${target} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  endif()
  target_link_libraries(${target} PUBLIC shellflow::shellflow ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE})
  target_precompile_headers(${target} REUSE_FROM shellflow)
endfunction()
