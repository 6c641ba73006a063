#pragma once
// The resource scenes, loaded once per test binary (loading builds textures and is not free).
#include <map>
#include <string>

#include "uav/world/scene.hpp"

namespace uav::test {

inline const world::Scene& CachedScene(const std::string& name) {
  static std::map<std::string, world::Scene> cache;
  auto it = cache.find(name);
  if (it == cache.end())
    it = cache.emplace(name, world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/" + name + ".scene.json")).first;
  return it->second;
}

}  // namespace uav::test
