# Compiler settings shared by every shellflow target.

set(CMAKE_CXX_STANDARD 20)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(CMAKE_CXX_EXTENSIONS OFF)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)
set(CMAKE_EXPORT_COMPILE_COMMANDS ON)

# ccache, when installed (scripts/setup.sh installs it), so that rebuilds in a session and CI's
# build after it reuse objects. base_dir makes the cache key relative to the source root and
# NOHASHDIR keeps the build folder out of it where there is debug information (the Sanitize
# build's line tables), so a clone in another folder hits too; the sloppiness lets
# precompiled headers be cached.
find_program(SHELLFLOW_CCACHE ccache)
if(SHELLFLOW_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  set(CMAKE_CXX_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${PROJECT_SOURCE_DIR}
      CCACHE_NOHASHDIR=1
      CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime
      ${SHELLFLOW_CCACHE})
endif()

# Plugins land in one folder of the build tree so the loader finds them there.
set(SHELLFLOW_PLUGIN_OUTPUT_DIR ${PROJECT_BINARY_DIR}/lib/shellflow/plugins)
set(SHELLFLOW_PLUGIN_INSTALL_DIR lib/shellflow/plugins)

# The "Sanitize" build type: AddressSanitizer + UndefinedBehaviorSanitizer.
# SHELLFLOW_SANITIZE_COMPILE/LINK_OPTIONS are also what an installed Sanitize build hands
# to plugins built against it (framework/CMakeLists.txt, shellflow::sdk).
set(SHELLFLOW_SANITIZE_COMPILE_OPTIONS
    -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined)
set(SHELLFLOW_SANITIZE_LINK_OPTIONS -fsanitize=address,undefined)
list(JOIN SHELLFLOW_SANITIZE_COMPILE_OPTIONS " " _sanitize_compile_flags)
# -g1: line tables only, what a sanitizer's stack trace reads (full -g made CI's sanitizer
# build slower to compile and link for no line of a report).
set(CMAKE_CXX_FLAGS_SANITIZE "-O1 -g1 ${_sanitize_compile_flags}"
    CACHE STRING "Flags for the Sanitize build type" FORCE)
set(CMAKE_EXE_LINKER_FLAGS_SANITIZE "${SHELLFLOW_SANITIZE_LINK_OPTIONS}" CACHE STRING "" FORCE)
set(CMAKE_SHARED_LINKER_FLAGS_SANITIZE "${SHELLFLOW_SANITIZE_LINK_OPTIONS}" CACHE STRING "" FORCE)
set(CMAKE_MODULE_LINKER_FLAGS_SANITIZE "${SHELLFLOW_SANITIZE_LINK_OPTIONS}" CACHE STRING "" FORCE)

# shellflow_target_defaults(<target>): warnings on every target we own.
function(shellflow_target_defaults target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  # -Winvalid-pch: a precompiled header that a target cannot use says so, not slows it silently.
  target_compile_options(${target} PRIVATE -Wall -Wextra -Winvalid-pch)
  if(SHELLFLOW_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# shellflow_precompile_headers(<target> [<extra headers>...]): precompile the third-party and
# standard headers nearly every translation unit includes (Eigen and nlohmann-json dominate
# the build's time), plus the target's extras. Other targets take it with
# target_precompile_headers(<t> REUSE_FROM <target>).
set(SHELLFLOW_COMMON_PCH_HEADERS
  <algorithm> <array> <cmath> <filesystem> <functional> <map> <memory> <optional> <string>
  <vector> <Eigen/Core> <Eigen/Geometry> <nlohmann/json.hpp>)
function(shellflow_precompile_headers target)
  target_precompile_headers(${target} PRIVATE ${SHELLFLOW_COMMON_PCH_HEADERS} ${ARGN})
endfunction()
