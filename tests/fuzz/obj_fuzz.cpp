// Wavefront OBJ (app/render/mesh.hpp load_obj) with the material library it may name
// (`mtllib m.mtl`, the input's second part).
#include "app/render/mesh.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace probeless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::write_parts(fuzz::as_text(data, size), {"model.obj", "m.mtl"});
  fuzz::expect_accept_or_refuse([] { render::load_obj(fuzz::scratch_dir() / "model.obj"); });
  return 0;
}
