#include "uav/shared/mono_depth.hpp"

namespace uav {

const char* Name(CellState s) {
  switch (s) {
    case CellState::kUnknown: return "unknown";
    case CellState::kFree: return "free";
    case CellState::kObstacle: return "obstacle";
  }
  return "unknown";
}

}  // namespace uav
