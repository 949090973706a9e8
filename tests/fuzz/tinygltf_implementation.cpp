// tinygltf's implementation, compiled into the glTF harness with the harness's instrumentation:
// Debian's libtinygltf.so is built without coverage counters or sanitizers, so a harness that
// only linked it would fuzz tinygltf's JSON and buffer parsing blind. The definitions here come
// first in the link and are the ones the reader calls.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
