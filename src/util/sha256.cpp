#include "util/sha256.h"

#include <stdexcept>

#include <openssl/evp.h>

namespace hrbench {

namespace {

std::string HexOf(const unsigned char *digest, unsigned int size) {
    static constexpr char kDigits[] = "0123456789abcdef";
    std::string hex;
    for (unsigned int k = 0; k < size; ++k) {
        hex += kDigits[digest[k] >> 4];
        hex += kDigits[digest[k] & 15];
    }
    return hex;
}

[[noreturn]] void Failed() { throw std::runtime_error("OpenSSL's SHA-256 failed"); }

}  // namespace

std::string Sha256Hex(std::string_view bytes) {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int size = 0;
    if (!EVP_Digest(bytes.data(), bytes.size(), digest, &size, EVP_sha256(), nullptr))
        Failed();
    return HexOf(digest, size);
}

Sha256::Sha256() : context_(EVP_MD_CTX_new()) {
    if (!context_ ||
        !EVP_DigestInit_ex(static_cast<EVP_MD_CTX *>(context_), EVP_sha256(), nullptr)) {
        EVP_MD_CTX_free(static_cast<EVP_MD_CTX *>(context_));
        Failed();
    }
}

Sha256::~Sha256() { EVP_MD_CTX_free(static_cast<EVP_MD_CTX *>(context_)); }

void Sha256::Update(std::string_view bytes) {
    if (!EVP_DigestUpdate(static_cast<EVP_MD_CTX *>(context_), bytes.data(), bytes.size()))
        Failed();
}

std::string Sha256::Hex() {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int size = 0;
    if (!EVP_DigestFinal_ex(static_cast<EVP_MD_CTX *>(context_), digest, &size))
        Failed();
    return HexOf(digest, size);
}

}  // namespace hrbench
