# Script mode helper of EmbedCl.cmake: IN (the .cl), OUT (the header), NAME (identifier).
file(READ "${IN}" text)
string(FIND "${text}" ")PROBELESS_CL\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${IN} contains the raw-string delimiter")
endif()
file(WRITE "${OUT}.tmp"
  "// Generated from ${IN} by cmake/EmbedCl.cmake; do not edit.\n"
  "#pragma once\n#include <string_view>\n"
  "namespace probeless::cl_source {\n"
  "inline constexpr std::string_view ${NAME} = R\"PROBELESS_CL(${text})PROBELESS_CL\";\n"
  "}\n")
file(COPY_FILE "${OUT}.tmp" "${OUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUT}.tmp")
