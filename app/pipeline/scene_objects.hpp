#pragma once
#include <filesystem>
#include <vector>

#include "app/pipeline/service_config.hpp"
#include "app/render/renderer.hpp"
#include "drivers/source.hpp"

namespace probeless {

// Where objects stand on a rig that knows no object anchor (a camera, a recording): the
// synthetic rig's table anchor, which its recordings share (docs/configuration.md). The sim
// tests hold it equal to sim::object_anchor().
Eigen::Vector3d default_object_anchor();
// Where an object's lowest point stands: its position, else the rig's object anchor (or
// default_object_anchor()) moved by its anchor_offset.
Eigen::Vector3d object_position(const ObjectConfig& object, const RigScene& scene);
// Sets every object's position (object_position()): once the rig is known.
void place_objects(std::vector<ObjectConfig>& objects, const RigScene& scene);

// Virtual objects from config: meshes built or loaded once, placed in the world frame. An
// object's `position` is where its lowest point stands (so a sphere rests on the table rather
// than sinking into it); without one, object_position() with no rig anchor.
//
// Materials map to render::Material::Shading (docs/rendering.md). A `prt` object's transfer
// is baked at load (app/render/prt/, with the ground plane under it blocking the light from
// below) and cached in `prt_cache_dir` (empty: no cache). With [ground] enabled and any
// image-based object, a last object is added: the ground receiver of differential rendering
// (Material::Shading::GroundShadow), a grid on the plane whose transfer is the difference the
// objects make (baked for all objects together, as one mesh; docs/rendering.md "Shadows on the
// real ground").
std::vector<render::VirtualObject> make_scene_objects(
    const std::vector<ObjectConfig>& objects, const GroundConfig& ground = {},
    const std::filesystem::path& prt_cache_dir = {});

// The same objects with every material replaced by the placeholder Lambert and without the
// ground receiver: what is drawn until the light capture has a snapshot.
std::vector<render::VirtualObject> placeholder_objects(
    const std::vector<render::VirtualObject>& objects);

// The renderer's configuration for these objects: only the rough metal reads the prefiltered
// levels; without one, a light update is an upload and the box chain (~2.4 ms) instead of the
// GGX pass as well (~11 ms at 128 px faces).
render::RendererConfig renderer_config_for(const std::vector<render::VirtualObject>& objects);

// Where baked transfer is kept: $PROBELESS_CACHE_DIR/prt, systemd's CacheDirectory/prt,
// $XDG_CACHE_HOME/probeless/prt or ~/.cache/probeless/prt (as the OpenCL program cache).
std::filesystem::path default_prt_cache_dir();

}  // namespace probeless
