// Bytes for the glTF reader tests: little-endian values appended to a string, and a binary glTF container (GLB)
// around a JSON chunk and a BIN chunk, each padded to 4 bytes as the format asks.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>

template <class T>
void put(std::string& s, T value) {
    char b[sizeof value];
    std::memcpy(b, &value, sizeof value);
    s.append(b, sizeof b);
}

inline std::string glb(std::string json, std::string bin) {
    while (json.size() % 4) json += ' ';
    while (bin.size() % 4) bin += '\0';
    std::string s;
    put(s, uint32_t(0x46546C67));  // "glTF"
    put(s, uint32_t(2));
    put(s, uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    put(s, uint32_t(json.size()));
    put(s, uint32_t(0x4E4F534A));  // "JSON"
    s += json;
    put(s, uint32_t(bin.size()));
    put(s, uint32_t(0x004E4942));  // "BIN\0"
    return s + bin;
}
