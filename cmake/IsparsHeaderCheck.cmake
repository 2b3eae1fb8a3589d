# Every header compiles on its own. `ispars_check_headers(TARGET DIR...)` adds the object library
# <TARGET>_headers: one translation unit per header (*.hpp) under each DIR of the calling folder,
# which includes that header and nothing else, compiled with TARGET's own include directories,
# definitions and options and everything TARGET links (so with TARGET's dependencies' usage
# requirements, and ispars_build_flags' warnings as errors). A header that compiles only after
# another include fails it, naming the header. A header that one of TARGET's sources includes
# first is left out: compiling that source (never in a unity build in deploy/test.sh's Release
# pass) compiles the header on its own already. Call it once TARGET is complete.
#
# Not part of `all`: `cmake --build build --target ispars_headers_check` builds every check
# (deploy/test.sh does). Never a unity build: each header is its own translation unit. Each is
# parsed, not compiled (cmake/parse_only.sh): what a header lacks is a parse error.
add_custom_target(ispars_headers_check)

# The headers TARGET's own sources include first: compiling such a source compiles its first
# header on its own already, so the check leaves those out (to `out`, as include paths).
function(ispars_first_includes target out)
  get_target_property(sources ${target} SOURCES)
  set(first_includes)
  foreach(source IN LISTS sources)
    get_filename_component(path ${source} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
    if(path MATCHES "\\.cpp$" AND EXISTS ${path})
      file(STRINGS ${path} first REGEX "^#include" LIMIT_COUNT 1)
      if(first MATCHES "^#include [\"<]([^\">]+)[\">]")
        list(APPEND first_includes ${CMAKE_MATCH_1})
      endif()
    endif()
  endforeach()
  set(${out} ${first_includes} PARENT_SCOPE)
endfunction()

function(ispars_check_headers target)
  set(headers)
  foreach(dir IN LISTS ARGN)
    file(GLOB_RECURSE found CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${dir}/*.hpp)
    list(APPEND headers ${found})
  endforeach()
  list(SORT headers)
  if(NOT headers)
    message(FATAL_ERROR "ispars_check_headers(${target}): no header under ${ARGN}")
  endif()
  ispars_first_includes(${target} first_includes)
  set(unchecked)
  foreach(header IN LISTS headers)
    foreach(included IN LISTS first_includes)
      string(LENGTH "/${included}" tail)
      string(LENGTH "${header}" length)
      if(length GREATER tail)
        math(EXPR at "${length} - ${tail}")
        string(SUBSTRING "${header}" ${at} ${tail} ending)
        if(ending STREQUAL "/${included}")
          list(APPEND unchecked ${header})
          break()
        endif()
      endif()
    endforeach()
  endforeach()
  if(unchecked)
    list(REMOVE_ITEM headers ${unchecked})
  endif()
  if(NOT headers)
    return()  # every header is some source's first include
  endif()
  set(sources)
  foreach(header IN LISTS headers)
    file(RELATIVE_PATH name ${PROJECT_SOURCE_DIR} ${header})
    string(MAKE_C_IDENTIFIER ${name} id)
    set(source ${CMAKE_CURRENT_BINARY_DIR}/header_check/${id}.cpp)
    file(CONFIGURE OUTPUT ${source} CONTENT "// ${name} on its own (cmake/IsparsHeaderCheck.cmake)\n#include \"${header}\"\n")
    list(APPEND sources ${source})
  endforeach()

  set(check ${target}_headers)
  add_library(${check} OBJECT EXCLUDE_FROM_ALL ${sources})
  set_target_properties(${check} PROPERTIES UNITY_BUILD OFF
                        CXX_COMPILER_LAUNCHER ${PROJECT_SOURCE_DIR}/cmake/parse_only.sh)
  foreach(property CXX_VISIBILITY_PRESET VISIBILITY_INLINES_HIDDEN POSITION_INDEPENDENT_CODE)
    get_target_property(value ${target} ${property})
    if(NOT value STREQUAL "value-NOTFOUND")
      set_property(TARGET ${check} PROPERTY ${property} ${value})
    endif()
  endforeach()
  foreach(property INCLUDE_DIRECTORIES COMPILE_DEFINITIONS COMPILE_OPTIONS)
    get_target_property(values ${target} ${property})
    if(values)
      set_property(TARGET ${check} APPEND PROPERTY ${property} ${values})
    endif()
  endforeach()
  get_target_property(libraries ${target} LINK_LIBRARIES)
  if(libraries)
    target_link_libraries(${check} PRIVATE ${libraries})
  endif()
  # The headers of a library need its own interface too (its include root, its public links).
  get_target_property(type ${target} TYPE)
  if(NOT type STREQUAL "EXECUTABLE" AND NOT type STREQUAL "MODULE_LIBRARY")
    target_link_libraries(${check} PRIVATE ${target})
  endif()
  add_dependencies(ispars_headers_check ${check})
endfunction()
