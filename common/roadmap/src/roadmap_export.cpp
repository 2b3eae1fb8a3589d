#include "ispars/roadmap/roadmap_export.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <iterator>

#include "ispars/roadmap/roadmap_batch.hpp"

namespace ispars {

std::string roadmap_ply(const Roadmap& roadmap) {
  std::string out;
  auto it = std::back_inserter(out);
  fmt::format_to(it,
                 "ply\nformat ascii 1.0\ncomment ispars roadmap: {} POIs, digest {:#018x}\nelement vertex {}\n"
                 "property double x\nproperty double y\nproperty double z\nproperty uint pois\nelement edge {}\n"
                 "property uint vertex1\nproperty uint vertex2\nend_header\n",
                 roadmap.poi_count(), roadmap_digest(roadmap), roadmap.vertex_count(), roadmap.edge_count());
  for (VertexId v = 0; v < roadmap.vertex_count(); ++v) {
    const Vec3& p = roadmap.position(v);
    std::size_t seen = 0;
    for (const std::uint64_t word : roadmap.visible(v)) seen += static_cast<std::size_t>(__builtin_popcountll(word));
    fmt::format_to(it, "{} {} {} {}\n", p.x(), p.y(), p.z(), seen);
  }
  for (const EdgeEnds& e : roadmap.edge_ends()) fmt::format_to(it, "{} {}\n", e.u, e.v);
  return out;
}

std::string roadmap_graphml(const Roadmap& roadmap) {
  std::string out =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<graphml xmlns=\"http://graphml.graphdrawing.org/xmlns\">\n"
      "  <key id=\"x\" for=\"node\" attr.name=\"x\" attr.type=\"double\"/>\n"
      "  <key id=\"y\" for=\"node\" attr.name=\"y\" attr.type=\"double\"/>\n"
      "  <key id=\"z\" for=\"node\" attr.name=\"z\" attr.type=\"double\"/>\n"
      "  <key id=\"pois\" for=\"node\" attr.name=\"pois\" attr.type=\"string\"/>\n"
      "  <key id=\"weight\" for=\"edge\" attr.name=\"weight\" attr.type=\"double\"/>\n"
      "  <graph id=\"roadmap\" edgedefault=\"undirected\">\n";
  auto it = std::back_inserter(out);
  for (VertexId v = 0; v < roadmap.vertex_count(); ++v) {
    const Vec3& p = roadmap.position(v);
    fmt::format_to(it,
                   "    <node id=\"n{}\"><data key=\"x\">{}</data><data key=\"y\">{}</data><data key=\"z\">{}</data>",
                   v, p.x(), p.y(), p.z());
    fmt::format_to(it, "<data key=\"pois\">{}</data></node>\n", fmt::join(roadmap.visibility_table().ids(v), " "));
  }
  for (std::size_t k = 0; k < roadmap.edge_count(); ++k) {
    const EdgeEnds e = roadmap.edge_ends()[k];
    fmt::format_to(it, "    <edge id=\"e{}\" source=\"n{}\" target=\"n{}\"><data key=\"weight\">{}</data></edge>\n", k,
                   e.u, e.v, (roadmap.position(e.u) - roadmap.position(e.v)).norm());
  }
  out += "  </graph>\n</graphml>\n";
  return out;
}

}  // namespace ispars
