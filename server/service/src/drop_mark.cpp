#include "ispars/service/drop_mark.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <sstream>

#include "ispars/roadmap/record_file.hpp"
#include "ispars/roadmap/sealed_file.hpp"

namespace ispars::service {
namespace {

std::filesystem::path marks_dir(const std::filesystem::path& data_dir) { return data_dir / ".drops"; }

std::filesystem::path mark_path(const std::filesystem::path& store_dir) {
  return marks_dir(store_dir.parent_path()) / store_dir.filename();
}

std::optional<std::uint64_t> parse(const std::optional<std::string>& text, const std::filesystem::path& path) {
  if (!text) return std::nullopt;
  const SealedText sealed = open_sealed_text(*text);
  if (sealed.seal == Seal::broken) {
    spdlog::error("drop mark {} fails its checksum (changed or damaged): not believed, left as it is", path.string());
    return std::nullopt;
  }
  std::istringstream in(sealed.body);
  std::string word;
  std::uint64_t generation = 0;
  if (!(in >> word >> generation) || word != "generation" || generation == 0) return std::nullopt;
  return generation;
}

}  // namespace

void mark_dropped(const std::filesystem::path& store_dir, std::uint64_t generation, FileSystem& fs) {
  const std::filesystem::path dir = marks_dir(store_dir.parent_path());
  if (fs.create_directories(dir)) fsync_directory_of(dir, fs);
  write_file_atomically(
      mark_path(store_dir),
      seal_text(fmt::format("generation {}\ndropped by request: the fleet weighs this empty roadmap like "
                            "any copy, so older copies elsewhere do not serve the scene again\n",
                            generation)),
      fs);
}

std::optional<std::uint64_t> dropped_generation(const std::filesystem::path& store_dir, const FileSystem& fs) {
  return parse(fs.read(mark_path(store_dir)), mark_path(store_dir));
}

std::vector<DropMark> list_drop_marks(const std::filesystem::path& data_dir, const FileSystem& fs) {
  std::vector<DropMark> out;
  for (const std::string& name : fs.list(marks_dir(data_dir))) {
    if (name.ends_with(".tmp")) continue;  // an interrupted write's temporary file
    const std::filesystem::path path = marks_dir(data_dir) / name;
    if (const auto generation = parse(fs.read(path), path)) out.push_back({name, *generation});
  }
  return out;
}

}  // namespace ispars::service
