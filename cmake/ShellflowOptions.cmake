# Compiler settings shared by every shellflow target.

set(CMAKE_CXX_STANDARD 20)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(CMAKE_CXX_EXTENSIONS OFF)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)
set(CMAKE_EXPORT_COMPILE_COMMANDS ON)

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
set(CMAKE_CXX_FLAGS_SANITIZE "-O1 -g ${_sanitize_compile_flags}"
    CACHE STRING "Flags for the Sanitize build type" FORCE)
set(CMAKE_EXE_LINKER_FLAGS_SANITIZE "${SHELLFLOW_SANITIZE_LINK_OPTIONS}" CACHE STRING "" FORCE)
set(CMAKE_SHARED_LINKER_FLAGS_SANITIZE "${SHELLFLOW_SANITIZE_LINK_OPTIONS}" CACHE STRING "" FORCE)
set(CMAKE_MODULE_LINKER_FLAGS_SANITIZE "${SHELLFLOW_SANITIZE_LINK_OPTIONS}" CACHE STRING "" FORCE)

# shellflow_target_defaults(<target>): warnings on every target we own.
function(shellflow_target_defaults target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  if(SHELLFLOW_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
