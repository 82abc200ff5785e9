# probeless_warnings(<target>): the project's warning set, as errors when PROBELESS_WERROR.
function(probeless_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
    -Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual -Wnull-dereference
    -Wimplicit-fallthrough)
  if(PROBELESS_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
