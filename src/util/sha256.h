// SHA-256 (FIPS 180-4) of a byte string, by OpenSSL, for the scene digest
// (docs/scene-format.md).
#pragma once

#include <string>
#include <string_view>

namespace hrbench {

// The SHA-256 digest of _bytes_ as 64 lower-case hexadecimal digits.
std::string Sha256Hex(std::string_view bytes);

// The SHA-256 digest of bytes given piece by piece, so that a long text need not be held
// whole: Hex() after Update(a), Update(b) equals Sha256Hex(a + b).
class Sha256 {
  public:
    Sha256();
    ~Sha256();
    Sha256(const Sha256 &) = delete;
    Sha256 &operator=(const Sha256 &) = delete;

    void Update(std::string_view bytes);
    // The digest of everything given, as Sha256Hex writes it; call once, at the end.
    std::string Hex();

  private:
    void *context_;  // OpenSSL's EVP_MD_CTX, kept out of this header
};

}  // namespace hrbench
