// SHA-256 (FIPS 180-4) of a byte string, by OpenSSL, for the scene digest
// (docs/scene-format.md).
#pragma once

#include <string>
#include <string_view>

namespace hrbench {

// The SHA-256 digest of _bytes_ as 64 lower-case hexadecimal digits.
std::string Sha256Hex(std::string_view bytes);

}  // namespace hrbench
