# Run after lcm-gen (cmake -DDIR=<dir of generated .hpp> -P harden_decoders.cmake). LCM 1.4's C++
# decoders trust the lengths they read: a string length of 0 or less reaches std::string::assign
# as a huge count (it throws out of the bus handler), and an array count is passed to
# std::vector::resize before any bounds check (a negative one throws, a large one allocates and
# zeroes up to gigabytes for a 100-byte datagram). Every element takes at least one byte, so a
# count larger than the bytes left is refused as the malformed message it is, before allocating.
file(GLOB headers "${DIR}/*.hpp")
foreach(h ${headers})
  file(READ "${h}" text)
  string(REGEX REPLACE "if\\(__([A-Za-z0-9_]+)_len__ > maxlen - pos\\) return -1;"
         "if(__\\1_len__ < 1 || __\\1_len__ > maxlen - pos) return -1;" text "${text}")
  string(REGEX REPLACE "this->([A-Za-z0-9_]+)\\.resize\\(this->([A-Za-z0-9_]+)\\);"
         "if(this->\\2 < 0 || this->\\2 > maxlen - pos) return -1; this->\\1.resize(this->\\2);" text "${text}")
  file(WRITE "${h}" "${text}")
endforeach()
