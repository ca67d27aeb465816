# The folders under results/ are named once, in scripts/results_layout.sh (the shell scripts
# source it, the report parses it). This reads its NAME=folder lines into a header of C++
# constants, kResults<Name> (VERDICT → kResultsVerdict), for the programs whose defaults name a
# folder there: the interface library puppet_results_layout. Configuring again on a change.
set(PUPPET_LAYOUT_FILE ${PROJECT_SOURCE_DIR}/scripts/results_layout.sh)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PUPPET_LAYOUT_FILE})
file(STRINGS ${PUPPET_LAYOUT_FILE} puppet_layout_lines REGEX "^[A-Z_]+=")
set(PUPPET_LAYOUT_CONSTANTS "")
foreach(line IN LISTS puppet_layout_lines)
  if(NOT line MATCHES "^([A-Z_]+)=([^ \t#]+)")
    message(FATAL_ERROR "${PUPPET_LAYOUT_FILE}: not a NAME=folder line: ${line}")
  endif()
  set(folder ${CMAKE_MATCH_2})
  string(TOLOWER ${CMAKE_MATCH_1} name)
  string(REPLACE "_" ";" words ${name})
  set(camel "")
  foreach(word IN LISTS words)
    string(SUBSTRING ${word} 0 1 first)
    string(TOUPPER ${first} first)
    string(SUBSTRING ${word} 1 -1 rest)
    string(APPEND camel ${first}${rest})
  endforeach()
  string(APPEND PUPPET_LAYOUT_CONSTANTS
         "inline constexpr const char* kResults${camel} = \"${folder}\";\n")
endforeach()
configure_file(${CMAKE_CURRENT_LIST_DIR}/results_layout.h.in
               ${CMAKE_BINARY_DIR}/generated/puppet/results_layout.h @ONLY)
add_library(puppet_results_layout INTERFACE)
target_include_directories(puppet_results_layout INTERFACE ${CMAKE_BINARY_DIR}/generated)
