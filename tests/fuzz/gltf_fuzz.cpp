// glTF 2.0 (app/render/mesh.hpp load_gltf): binary .glb when the input starts with the glTF
// magic, JSON .gltf otherwise; buffers come from data: URIs (the seeds') or files beside it.
#include "app/render/mesh.hpp"
#include "tests/fuzz/fuzz_support.hpp"

using namespace probeless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = fuzz::as_text(data, size);
  const bool binary = text.starts_with("glTF");
  const auto path = fuzz::write_scratch(binary ? "model.glb" : "model.gltf", text);
  fuzz::expect_accept_or_refuse([&] { render::load_gltf(path); });
  return 0;
}
