# nubot_add_kernels(SOURCES <file>... [LIBRARIES <target>...]): a package's compiled kernels, the pybind11
# extension module <package>._kernels (C++17, Eigen), built by catkin_make into the package's Python source folder
# (importable with or without a sourced workspace) and installed beside its Python modules.
#
# -DNUBOT_SANITIZE=ON builds them with AddressSanitizer and UndefinedBehaviorSanitizer into
# NUBOT_KERNELS_DIR/<package>/ instead (make sanitize: nubot_common.kernels loads them from there).

find_package(pybind11 2.10 CONFIG REQUIRED)  # Debian: pybind11-dev
find_package(Eigen3 3.3 REQUIRED NO_MODULE)  # Debian: libeigen3-dev

option(NUBOT_SANITIZE "build the kernels with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
set(NUBOT_KERNELS_DIR "" CACHE PATH "with NUBOT_SANITIZE: where the kernels are built, one folder per package")
if(NUBOT_SANITIZE AND NOT NUBOT_KERNELS_DIR)
  message(FATAL_ERROR "NUBOT_SANITIZE needs NUBOT_KERNELS_DIR: the sanitized kernels never replace the normal ones")
endif()

# Flags for C and C++ code in the kernels (DAQP's C sources too): optimised, with debug information, and under
# NUBOT_SANITIZE the sanitizers, which stop at the first error they find.
set(NUBOT_KERNEL_FLAGS -O2 -g)
set(NUBOT_KERNEL_LINK_FLAGS "")
if(NUBOT_SANITIZE)
  list(APPEND NUBOT_KERNEL_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  set(NUBOT_KERNEL_LINK_FLAGS -fsanitize=address,undefined)
endif()

function(nubot_add_kernels)
  cmake_parse_arguments(KERNELS "" "" "SOURCES;LIBRARIES" ${ARGN})
  set(target ${PROJECT_NAME}_kernels)
  # NO_EXTRAS: no link-time optimisation or stripping, so that the debug information and the sanitizers stay whole.
  pybind11_add_module(${target} MODULE NO_EXTRAS ${KERNELS_SOURCES})
  if(NUBOT_SANITIZE)
    set(output "${NUBOT_KERNELS_DIR}/${PROJECT_NAME}")
  else()
    set(output "${PROJECT_SOURCE_DIR}/src/${PROJECT_NAME}")
  endif()
  set_target_properties(${target} PROPERTIES OUTPUT_NAME _kernels LIBRARY_OUTPUT_DIRECTORY "${output}"
    CXX_STANDARD 17 CXX_STANDARD_REQUIRED ON CXX_EXTENSIONS OFF CXX_VISIBILITY_PRESET hidden)
  target_include_directories(${target} PRIVATE "${PROJECT_SOURCE_DIR}/include")
  target_compile_options(${target} PRIVATE ${NUBOT_KERNEL_FLAGS} -Wall -Wextra -Wpedantic -Wshadow
    -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Wunused -Woverloaded-virtual
    -Wdouble-promotion -Wformat=2)
  target_link_options(${target} PRIVATE ${NUBOT_KERNEL_LINK_FLAGS})
  target_link_libraries(${target} PRIVATE Eigen3::Eigen ${KERNELS_LIBRARIES})
  install(TARGETS ${target} LIBRARY DESTINATION ${CATKIN_PACKAGE_PYTHON_DESTINATION})
endfunction()
