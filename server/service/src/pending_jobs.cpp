#include "ispars/service/pending_jobs.hpp"

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include <iterator>
#include <optional>
#include <stdexcept>

#include "ispars/params/json_archive.hpp"
#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/roadmap/record_file.hpp"
#include "ispars/roadmap/sealed_file.hpp"
#include "ispars/service/scene_catalog.hpp"

namespace ispars::service {
namespace {

std::filesystem::path jobs_dir(const std::filesystem::path& data_dir) { return data_dir / ".jobs"; }
std::filesystem::path record_path(const std::filesystem::path& data_dir, const std::string& scene) {
  return jobs_dir(data_dir) / (scene + ".json");
}

nlohmann::json to_json(const PendingJob& job) {
  nlohmann::json j{{"scene", job.scene},
                   {"id", job.id},
                   {"target", job.target},
                   {"attempts", job.attempts},
                   {"stopped_cleanly", job.stopped_cleanly}};
  if (job.build) {
    const BuildRequest& b = *job.build;
    nlohmann::json overrides = nlohmann::json::object();
    params::write_json(b.overrides, overrides);
    j["build"] = {{"method", std::string(to_string(b.method))},
                  {"variant", std::string(to_string(b.variant.value_or(SparsVariant::stretch)))},
                  {"samples", b.samples},
                  {"seed", b.seed},
                  {"overrides", std::move(overrides)},
                  {"replace", b.replace},
                  {"lineage", b.generation}};
    j["generation"] = job.generation;
  }
  if (job.task) {
    nlohmann::json pois = nlohmann::json::array();
    for (const Vec3& p : job.task->pois) pois.push_back({p.x(), p.y(), p.z()});
    j["task"] = {{"name", job.task->name}, {"pois", std::move(pois)}};
  }
  return j;
}

PendingJob from_json(nlohmann::json j) {
  if (open_sealed_json(j) == Seal::broken) throw std::runtime_error("it fails its checksum (changed or damaged)");
  PendingJob job;
  job.scene = j.at("scene").get<std::string>();
  job.id = j.at("id").get<std::uint64_t>();
  job.target = j.at("target").get<std::uint64_t>();
  job.attempts = j.value("attempts", 0u);
  job.stopped_cleanly = j.value("stopped_cleanly", false);  // absent in records before clean stops were told apart
  if (j.contains("build")) {
    const nlohmann::json& b = j.at("build");
    BuildRequest r;
    const auto method = parse_build_method(b.at("method").get<std::string>());
    const auto variant = parse_spars_variant(b.at("variant").get<std::string>());
    if (!method || !variant) throw std::runtime_error("unknown method or variant");
    r.method = *method;
    if (has_variants(r.method)) r.variant = *variant;  // older records give one to every method
    r.samples = b.at("samples").get<std::uint64_t>();
    r.seed = b.at("seed").get<std::uint64_t>();
    // Each override under its name: a count as an integer, or as the double of records before
    // protocol 12 (read alike).
    params::read_json(b.at("overrides"), r.overrides, "pending job", "overrides.");
    r.replace = b.at("replace").get<bool>();
    r.generation = b.value("lineage", std::uint64_t{0});  // absent in records before takeovers kept lineages
    job.build = r;
    job.generation = j.at("generation").get<std::uint64_t>();
  }
  if (j.contains("task")) {
    const nlohmann::json& t = j.at("task");
    InspectionTask task;
    task.name = t.at("name").get<std::string>();
    for (const auto& p : t.at("pois")) {
      const auto xyz = p.get<std::vector<double>>();
      if (xyz.size() != 3) throw std::runtime_error("a task POI is not three numbers");
      task.pois.emplace_back(xyz[0], xyz[1], xyz[2]);
    }
    job.task = std::move(task);
  }
  return job;
}

}  // namespace

void save_pending_job(const std::filesystem::path& data_dir, const PendingJob& job, FileSystem& fs) {
  if (fs.create_directories(jobs_dir(data_dir))) fsync_directory_of(jobs_dir(data_dir), fs);
  write_file_atomically(record_path(data_dir, job.scene), seal_json(to_json(job)).dump(2) + "\n", fs);
}

void forget_pending_job(const std::filesystem::path& data_dir, const std::string& scene, std::uint64_t id,
                        FileSystem& fs) {
  const auto path = record_path(data_dir, scene);
  if (id != 0) {
    const std::optional<std::string> bytes = fs.read(path);
    if (!bytes) return;
    try {
      if (from_json(nlohmann::json::parse(*bytes)).id != id) return;  // a later job's record
    } catch (const std::exception&) {
      return;  // unreadable: left for inspection
    }
  }
  if (fs.remove(path)) fsync_directory_of(path, fs);
}

void mark_pending_jobs_stopped_cleanly(const std::filesystem::path& data_dir, FileSystem& fs) {
  for (PendingJob job : pending_jobs(data_dir, fs)) {
    if (job.stopped_cleanly) continue;
    job.stopped_cleanly = true;
    save_pending_job(data_dir, job, fs);
  }
}

std::vector<PendingJob> pending_jobs(const std::filesystem::path& data_dir, FileSystem& fs) {
  std::vector<PendingJob> out;
  for (const std::string& name : fs.list(jobs_dir(data_dir))) {
    const std::filesystem::path path = jobs_dir(data_dir) / name;
    if (path.extension() == ".tmp") {
      try {
        (void)fs.remove(path);  // a write a crash interrupted; its record is whole or absent
      } catch (const std::exception& e) {
        spdlog::warn("the interrupted pending job record {} could not be removed: {}", path.string(), e.what());
      }
      continue;
    }
    if (path.extension() != ".json") continue;
    try {
      const std::optional<std::string> bytes = fs.read(path);
      if (!bytes) continue;  // removed since the listing
      PendingJob job = from_json(nlohmann::json::parse(*bytes));
      if (job.scene + ".json" != name || !valid_scene_name(job.scene)) {
        throw std::runtime_error("its scene does not match its name");
      }
      out.push_back(std::move(job));
    } catch (const std::exception& e) {
      spdlog::error("pending job record {} is unreadable ({}); left as it is, not resumed", path.string(), e.what());
    }
  }
  return out;
}

}  // namespace ispars::service
