#include "ispars/scene_files/scene_config.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "ispars/params/fields.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/scene_files/procedural.hpp"

namespace ispars::scene_files {
namespace {

// Reads fields of one YAML map, naming the file and the dotted field path in every error.
class FieldReader {
 public:
  FieldReader(const std::string& source, YAML::Node node, std::string prefix)
      : source_(source), node_(std::move(node)), prefix_(std::move(prefix)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& problem) const {
    throw params::InputError(source_, prefix_ + key, problem);
  }

  [[nodiscard]] bool has(const std::string& key) const { return static_cast<bool>(node_[key]); }

  [[nodiscard]] YAML::Node child(const std::string& key) const {
    const YAML::Node value = node_[key];
    if (!value) fail(key, "missing (required)");
    return value;
  }

  [[nodiscard]] FieldReader map(const std::string& key) const {
    const YAML::Node value = child(key);
    if (!value.IsMap()) fail(key, "expected a mapping, e.g. {min: [...], max: [...]}");
    return FieldReader(source_, value, prefix_ + key + ".");
  }

  // The declared parameter `spec`, read as a finite YAML number and checked against its range.
  [[nodiscard]] double parameter(const params::Spec<double>& spec) const {
    const std::string key(spec.name);
    const double number = to_number(child(key), key);
    if (std::string p = params::problem(spec, number); !p.empty()) fail(key, p);
    return number;
  }

  [[nodiscard]] std::uint64_t whole(const std::string& key) const {
    const YAML::Node value = child(key);
    const std::string text = value.IsScalar() ? value.Scalar() : "";
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 19) {
      fail(key, fmt::format("expected a whole number >= 0, got '{}'", describe(value)));
    }
    return std::stoull(text);
  }

  [[nodiscard]] bool boolean(const std::string& key) const {
    const YAML::Node value = child(key);
    try {
      return value.as<bool>();
    } catch (const YAML::Exception&) {
      fail(key, fmt::format("expected true or false, got '{}'", describe(value)));
    }
  }

  [[nodiscard]] std::string text(const std::string& key) const {
    const YAML::Node value = child(key);
    if (!value.IsScalar() || value.Scalar().empty()) fail(key, "expected a non-empty string");
    return value.Scalar();
  }

  [[nodiscard]] Vec3 point(const std::string& key) const {
    const YAML::Node value = child(key);
    if (!value.IsSequence() || value.size() != 3) {
      fail(key, fmt::format("expected three numbers [x, y, z], got '{}'", describe(value)));
    }
    Vec3 p;
    for (std::size_t i = 0; i < 3; ++i) p[static_cast<Eigen::Index>(i)] = to_number(value[i], key);
    return p;
  }

  // Rejects keys outside `known`, and any key given twice (YAML parsers keep just one).
  void reject_unknown(const std::set<std::string>& known) const {
    std::set<std::string> seen;
    for (const auto& entry : node_) {
      const std::string key = entry.first.as<std::string>();
      if (!seen.insert(key).second) fail(key, "given twice");
      if (!known.count(key)) {
        std::string list;
        for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
        fail(key, "unknown field (known: " + list + ")");
      }
    }
  }

 private:
  static std::string describe(const YAML::Node& value) {
    YAML::Emitter out;
    out << YAML::Flow << value;
    return out.c_str();
  }

  double to_number(const YAML::Node& value, const std::string& key) const {
    if (!value.IsScalar()) fail(key, fmt::format("expected a number, got '{}'", describe(value)));
    double number = 0.0;
    try {
      number = value.as<double>();
    } catch (const YAML::Exception&) {
      fail(key, fmt::format("expected a number, got '{}'", value.Scalar()));
    }
    if (!std::isfinite(number)) fail(key, fmt::format("must be finite, got {}", value.Scalar()));
    return number;
  }

  const std::string& source_;
  YAML::Node node_;
  std::string prefix_;
};

SceneConfig parse_root(const YAML::Node& root, const std::filesystem::path& base_dir, const std::string& source) {
  if (!root.IsMap()) throw params::InputError(source, "yaml", "expected a mapping of scene fields at the top level");
  const FieldReader top(source, root, "");
  std::set<std::string> known{"name", "mesh", "procedural", "bounds", "root", "pois"};
  const SceneConfig declared;
  params::visit(declared, [&](const auto& spec, const auto&) { known.insert(std::string(spec.name)); });
  top.reject_unknown(known);

  SceneConfig config;
  if (top.has("mesh") == top.has("procedural")) {
    top.fail("mesh", "give exactly one of 'mesh: FILE' or 'procedural: {kind, seed}'");
  }
  // A procedural scene starts from its generator's parameters; any field below overrides them.
  const bool procedural = top.has("procedural");
  if (procedural) {
    const FieldReader spec = top.map("procedural");
    spec.reject_unknown({"kind", "seed"});
    const std::string kind = spec.text("kind");
    if (!is_procedural_kind(kind)) {
      spec.fail("kind", "unknown kind '" + kind + "' (known: " + procedural_kinds_list() + ")");
    }
    config = procedural_scene_config(kind, spec.whole("seed"));
  } else {
    const std::filesystem::path mesh = top.text("mesh");
    config.mesh = mesh.is_absolute() ? mesh : base_dir / mesh;
  }
  config.source = source;
  if (top.has("name")) {
    config.name = top.text("name");
  } else if (!procedural) {
    config.name = std::filesystem::path(source).stem().string();
  }

  // Required for a mesh scene (scale aside: 1 by default); optional (generator default) for a
  // procedural one.
  params::visit(config, [&](const auto& spec, double& value) {
    const std::string key(spec.name);
    if (top.has(key) || (!procedural && &spec != &kScale)) value = top.parameter(spec);
  });
  if (top.has("bounds") || !procedural) {
    const FieldReader bounds = top.map("bounds");
    bounds.reject_unknown({"min", "max"});
    config.bounds.min = bounds.point("min");
    config.bounds.max = bounds.point("max");
  }
  if (top.has("root") || !procedural) config.root = top.point("root");

  if (top.has("pois") || !procedural) {
    const FieldReader pois = top.map("pois");
    pois.reject_unknown({"count", "seed", "skip_ground", "file"});
    config.pois = PoiSource{};
    if (pois.has("file")) {
      if (pois.has("count") || pois.has("seed")) {
        pois.fail("file", "give either 'file' or 'count' and 'seed', not both");
      }
      const std::filesystem::path file = pois.text("file");
      config.pois.file = file.is_absolute() ? file : base_dir / file;
    } else {
      const std::uint64_t count = pois.whole("count");
      if (count == 0 || count > 10'000'000) {
        pois.fail("count", fmt::format("must be 1 to 10000000, got {}", count));
      }
      config.pois.count = static_cast<std::size_t>(count);
      config.pois.seed = pois.whole("seed");
    }
    if (pois.has("skip_ground")) config.pois.skip_ground = pois.boolean("skip_ground");
  }

  check_scene_config(config);
  return config;
}

}  // namespace

void check_scene_config(const SceneConfig& c) {
  const auto fail = [&](const std::string& field, const std::string& problem) {
    throw params::InputError(c.source, field, problem);
  };
  params::check(c, c.source);
  if (!c.bounds.min.allFinite() || !c.bounds.max.allFinite()) fail("bounds", "must be finite");
  for (int i = 0; i < 3; ++i) {
    if (!(c.bounds.min[i] < c.bounds.max[i])) {
      fail("bounds", fmt::format("min must be below max on every axis; axis {} has min {} >= max {}", "xyz"[i],
                                 c.bounds.min[i], c.bounds.max[i]));
    }
  }
  if (!c.root.allFinite()) fail("root", "must be finite");
  if (!c.bounds.contains(c.root)) {
    fail("root", fmt::format("[{}, {}, {}] is outside the bounds [{}, {}, {}] .. [{}, {}, {}]", c.root.x(), c.root.y(),
                             c.root.z(), c.bounds.min.x(), c.bounds.min.y(), c.bounds.min.z(), c.bounds.max.x(),
                             c.bounds.max.y(), c.bounds.max.z()));
  }
}

SceneConfig parse_scene_config_text(std::string_view text, const std::filesystem::path& base_dir,
                                    const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    throw params::InputError(source, "yaml",
                             fmt::format("line {}, column {}: {}", e.mark.line + 1, e.mark.column + 1, e.msg));
  }
  return parse_root(root, base_dir, source);
}

SceneConfig parse_scene_config(const std::filesystem::path& yaml_path) {
  const std::string source = yaml_path.string();
  std::error_code ec;
  if (!std::filesystem::exists(yaml_path, ec)) throw params::InputError(source, "file", "scene file does not exist");
  std::ifstream in(yaml_path);
  if (!in || std::filesystem::is_directory(yaml_path, ec)) {
    throw params::InputError(source, "file", "cannot read scene file");
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_scene_config_text(buffer.str(), yaml_path.parent_path(), source);
}

}  // namespace ispars::scene_files
