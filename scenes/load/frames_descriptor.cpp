#include "scenes/load/frames_descriptor.h"

#include "cdbench/core/error.h"
#include "scenes/load/replace_file.h"

namespace cdb {

nlohmann::ordered_json queries_json(const Topology& topology) {
  if (!topology.queries.declared) return nullptr;
  nlohmann::ordered_json self = nlohmann::ordered_json::array(), inter = nlohmann::ordered_json::array();
  for (uint32_t o : topology.queries.self) self.push_back(topology.objects.at(o).name);
  for (const auto& [a, b] : topology.queries.inter)
    inter.push_back({topology.objects.at(a).name, topology.objects.at(b).name});
  return {{"self", std::move(self)}, {"inter", std::move(inter)}};
}

bool write_frames_descriptor(const Topology& topology, const std::string& description, const std::filesystem::path& dir) {
  if (!topology.queries.declared) return false;
  nlohmann::ordered_json d = {{"description", description}, {"frames", "."}};
  nlohmann::ordered_json objects = nlohmann::ordered_json::array();
  for (const SceneObject& o : topology.objects) {
    nlohmann::ordered_json entry = {{"name", o.name}, {"faces", {o.first_face, o.num_faces}}};
    if (o.rigid) entry["rigid"] = true;
    objects.push_back(std::move(entry));
  }
  d["objects"] = std::move(objects);
  d["queries"] = queries_json(topology);

  const std::filesystem::path file = dir / kFramesDescriptorName;
  const std::string failed = replace_file(file, [&](std::ostream& os) { os << d.dump(2) << '\n'; });
  if (!failed.empty()) fail(failed + " (nothing left there)");
  return true;
}

}  // namespace cdb
