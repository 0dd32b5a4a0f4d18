#include "scenes/load/frames_descriptor.h"

#include <cerrno>
#include <cstring>
#include <fstream>

#include "cdbench/core/error.h"

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
  const std::filesystem::path part = dir / (std::string(kFramesDescriptorName) + ".part");
  {
    std::ofstream os(part, std::ios::trunc);
    os << d.dump(2) << '\n';
    os.close();
    if (!os) {
      const int error = errno;
      std::error_code ec;
      std::filesystem::remove(part, ec);
      fail(file.string() + ": write failed" + (error ? std::string(": ") + std::strerror(error) : "") +
           " (nothing left there)");
    }
  }
  std::error_code ec;
  std::filesystem::rename(part, file, ec);
  if (ec) {
    std::filesystem::remove(part, ec);
    fail(file.string() + ": cannot move the written descriptor into place: " + ec.message());
  }
  return true;
}

}  // namespace cdb
