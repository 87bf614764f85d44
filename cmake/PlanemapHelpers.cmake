# One place that sets the language level, warnings and include layout of every planemap target.

function(planemap_set_options target)
  target_compile_features(${target} PUBLIC cxx_std_17)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-unused-parameter)
endfunction()

# planemap_add_library(NAME SOURCES ... DEPENDS ...): a static library planemap_<NAME> with its
# public headers under <folder>/include/planemap/<NAME>/.
function(planemap_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS;PRIVATE_DEPENDS" ${ARGN})
  add_library(planemap_${name} STATIC ${ARG_SOURCES})
  add_library(planemap::${name} ALIAS planemap_${name})
  target_include_directories(planemap_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_link_libraries(planemap_${name} PUBLIC ${ARG_DEPENDS} PRIVATE ${ARG_PRIVATE_DEPENDS})
  planemap_set_options(planemap_${name})
endfunction()

# A folder whose code arrives with a later capability still states its place in the layering.
function(planemap_add_interface_library name)
  cmake_parse_arguments(ARG "" "" "DEPENDS" ${ARGN})
  add_library(planemap_${name} INTERFACE)
  add_library(planemap::${name} ALIAS planemap_${name})
  target_link_libraries(planemap_${name} INTERFACE ${ARG_DEPENDS})
endfunction()

function(planemap_enable_sanitizers_if_requested)
  if(PLANEMAP_SANITIZE)
    add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
    add_link_options(-fsanitize=address,undefined)
  endif()
endfunction()

# Faster links with lld when it is installed.
find_program(PLANEMAP_LLD ld.lld)
if(PLANEMAP_LLD)
  add_link_options(-fuse-ld=lld)
endif()
