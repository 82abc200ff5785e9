# probeless_embed_cl(<target> <stage.cl>...)
#
# Embeds each OpenCL source into the binary at build time. For
# kernels/occlusion/baselines/direct_matte.cl it generates
# <build>/generated/kernels/occlusion/baselines/direct_matte_cl.hpp declaring
#   namespace probeless::cl_source { inline constexpr std::string_view direct_matte = R"(...)"; }
# so the host class beside the .cl includes "kernels/occlusion/baselines/direct_matte_cl.hpp".
# The symbol is the file's stem alone, so no two .cl files may share one. The program cache
# hashes the text itself, so no hash is computed here.
set(_PROBELESS_EMBED_SCRIPT "${CMAKE_CURRENT_LIST_DIR}/EmbedClFile.cmake")
function(probeless_embed_cl target)
  set(gen_root "${PROJECT_BINARY_DIR}/generated")
  foreach(cl IN LISTS ARGN)
    get_filename_component(abs "${cl}" ABSOLUTE)
    file(RELATIVE_PATH rel "${PROJECT_SOURCE_DIR}" "${abs}")
    get_filename_component(rel_dir "${rel}" DIRECTORY)
    get_filename_component(stem "${cl}" NAME_WE)
    set(out "${gen_root}/${rel_dir}/${stem}_cl.hpp")
    add_custom_command(OUTPUT "${out}"
      COMMAND ${CMAKE_COMMAND} -DIN=${abs} -DOUT=${out} -DNAME=${stem}
              -P "${_PROBELESS_EMBED_SCRIPT}"
      DEPENDS "${abs}" "${_PROBELESS_EMBED_SCRIPT}"
      COMMENT "Embedding ${rel}" VERBATIM)
    target_sources(${target} PRIVATE "${out}")
  endforeach()
  target_include_directories(${target} PUBLIC "${gen_root}")
endfunction()
