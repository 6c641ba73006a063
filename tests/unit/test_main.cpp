// Every unit-test executable's main: the process keeps the memory it frees, as the flight stack
// does (uav/shared/process_memory.hpp), so flights inside the tests run as they do onboard.
#include <gtest/gtest.h>

#include "uav/shared/process_memory.hpp"

int main(int argc, char** argv) {
  uav::KeepFreedMemory();
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
