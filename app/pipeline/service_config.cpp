#include "app/pipeline/service_config.hpp"

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <toml++/toml.h>

#include "core/error.hpp"

namespace probeless {
namespace {

class Reader {
 public:
  Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const toml::node* node, const std::string& what) const {
    const int line = node ? static_cast<int>(node->source().begin.line) : 0;
    throw ParseError(source_, line, what);
  }

  // Rejects keys this version does not know, naming the first one.
  void only(const toml::table& table, std::string_view where,
            std::initializer_list<std::string_view> known) const {
    std::set<std::string_view> allowed(known);
    for (const auto& [key, node] : table)
      if (!allowed.contains(key.str()))
        fail(&node, "unknown key '" + std::string(key.str()) + "' in " + std::string(where));
  }

  template <typename T>
  void get(const toml::table& table, std::string_view key, T& out) const {
    const toml::node* node = table.get(key);
    if (!node) return;
    if constexpr (std::is_same_v<T, bool>) {
      if (!node->is_boolean()) fail(node, std::string(key) + ": expected true or false");
      out = node->as_boolean()->get();
    } else if constexpr (std::is_same_v<T, std::string>) {
      if (!node->is_string()) fail(node, std::string(key) + ": expected a string");
      out = node->as_string()->get();
    } else if constexpr (std::is_integral_v<T>) {
      if (!node->is_integer()) fail(node, std::string(key) + ": expected an integer");
      out = static_cast<T>(node->as_integer()->get());
    } else {
      auto v = node->value<double>();
      if (!v) fail(node, std::string(key) + ": expected a number");
      out = static_cast<T>(*v);
    }
  }

  template <int N, typename Scalar>
  void get_vector(const toml::table& table, std::string_view key,
                  Eigen::Matrix<Scalar, N, 1>& out) const {
    const toml::node* node = table.get(key);
    if (!node) return;
    const toml::array* arr = node->as_array();
    if (!arr || arr->size() != N)
      fail(node, std::string(key) + ": expected an array of " + std::to_string(N) + " numbers");
    for (int i = 0; i < N; ++i) {
      auto v = (*arr)[static_cast<std::size_t>(i)].value<double>();
      if (!v) fail(node, std::string(key) + ": expected numbers");
      out[i] = static_cast<Scalar>(*v);
    }
  }

  const toml::table* table(const toml::table& root, std::string_view key) const {
    const toml::node* node = root.get(key);
    if (!node) return nullptr;
    if (!node->is_table()) fail(node, std::string(key) + ": expected a table [" +
                                          std::string(key) + "]");
    return node->as_table();
  }

 private:
  std::string source_;
};

ObjectConfig parse_object(const Reader& r, const toml::table& t) {
  r.only(t, "[[object]]", {"shape", "model", "position", "yaw_deg", "scale", "color"});
  ObjectConfig o;
  r.get(t, "shape", o.shape);
  r.get(t, "model", o.model);
  if (t.get("position")) {
    Eigen::Vector3d p;
    r.get_vector<3>(t, "position", p);
    o.position = p;
  }
  r.get(t, "yaw_deg", o.yaw_deg);
  r.get(t, "scale", o.scale);
  r.get_vector<3>(t, "color", o.color);
  static const std::set<std::string> shapes{"pawn", "sphere", "box"};
  if (o.model.empty() && !shapes.contains(o.shape))
    r.fail(t.get("shape"), "shape '" + o.shape + "' is not one of pawn, sphere, box");
  if (!(o.scale > 0)) r.fail(t.get("scale"), "scale must be positive");
  return o;
}

}  // namespace

ServiceConfig parse_service_config(std::string_view text, std::string_view source_name) {
  const std::string source(source_name);
  toml::table root;
  try {
    root = toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    throw ParseError(source, static_cast<int>(e.source().begin.line),
                     std::string(e.description()));
  }
  Reader r(source);
  ServiceConfig c;
  r.only(root, "the top level", {"source", "object", "occlusion", "http", "output", "opencl",
                                 "pipeline"});
  if (auto* t = r.table(root, "source")) {
    r.only(*t, "[source]", {"rig"});
    r.get(*t, "rig", c.source);
  }
  if (const toml::node* node = root.get("object")) {
    const toml::array* arr = node->as_array();
    if (!arr || !arr->is_array_of_tables()) r.fail(node, "object: expected [[object]] tables");
    c.objects.clear();
    for (const auto& item : *arr) c.objects.push_back(parse_object(r, *item.as_table()));
  }
  if (auto* t = r.table(root, "occlusion")) {
    r.only(*t, "[occlusion]", {"method"});
    r.get(*t, "method", c.occlusion_method);
  }
  if (auto* t = r.table(root, "http")) {
    r.only(*t, "[http]", {"enabled", "address", "port", "jpeg_quality"});
    r.get(*t, "enabled", c.http_enabled);
    r.get(*t, "address", c.http_address);
    r.get(*t, "port", c.http_port);
    r.get(*t, "jpeg_quality", c.jpeg_quality);
    if (c.http_port < 0 || c.http_port > 65535) r.fail(t->get("port"), "port out of range");
    if (c.jpeg_quality < 1 || c.jpeg_quality > 100)
      r.fail(t->get("jpeg_quality"), "jpeg_quality must be 1..100");
  }
  if (auto* t = r.table(root, "output")) {
    r.only(*t, "[output]", {"dir", "format", "matte"});
    r.get(*t, "dir", c.output_dir);
    r.get(*t, "format", c.output_format);
    r.get(*t, "matte", c.output_matte);
    if (c.output_format != "jpeg" && c.output_format != "png")
      r.fail(t->get("format"), "format must be \"jpeg\" or \"png\"");
  }
  if (auto* t = r.table(root, "opencl")) {
    r.only(*t, "[opencl]", {"platform", "device"});
    r.get(*t, "platform", c.cl_platform);
    r.get(*t, "device", c.cl_device);
  }
  if (auto* t = r.table(root, "pipeline")) {
    r.only(*t, "[pipeline]", {"frames", "no_signal_after_ms"});
    r.get(*t, "frames", c.max_frames);
    r.get(*t, "no_signal_after_ms", c.no_signal_after_ms);
    if (c.no_signal_after_ms <= 0) r.fail(t->get("no_signal_after_ms"), "must be positive");
  }
  return c;
}

ServiceConfig load_service_config(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ParseError(path, 0, "cannot open the configuration file");
  std::stringstream ss;
  ss << in.rdbuf();
  ServiceConfig c = parse_service_config(ss.str(), path);
  // Model paths are relative to the file that names them.
  const auto dir = std::filesystem::path(path).parent_path();
  for (auto& o : c.objects)
    if (!o.model.empty() && std::filesystem::path(o.model).is_relative())
      o.model = (dir / o.model).string();
  return c;
}

}  // namespace probeless
