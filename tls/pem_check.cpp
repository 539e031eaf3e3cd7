#include "tls/pem_check.hpp"

#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/x509.h>
#include <pwd.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

#include <fmt/format.h>

namespace unima::tls {

namespace {

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};
struct X509Deleter {
  void operator()(X509* certificate) const { X509_free(certificate); }
};
struct KeyDeleter {
  void operator()(EVP_PKEY* key) const { EVP_PKEY_free(key); }
};
using X509Ptr = std::unique_ptr<X509, X509Deleter>;
using KeyPtr = std::unique_ptr<EVP_PKEY, KeyDeleter>;

// The reentrant form: a config from afar is checked on a worker thread while the loop may
// look up a control socket's peer.
std::string this_user() {
  passwd entry{};
  passwd* found = nullptr;
  std::array<char, 4096> buffer{};
  if (::getpwuid_r(::geteuid(), &entry, buffer.data(), buffer.size(), &found) == 0 && found) return found->pw_name;
  return fmt::format("uid {}", ::geteuid());
}

std::string text_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The file as OpenSSL will be given it, or why it cannot be opened.
std::optional<std::string> unopenable(const std::string& path) {
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return "no such file: correct the path, or put the file there";
    return fmt::format("cannot be looked at: {}", std::strerror(errno));
  }
  if (S_ISDIR(st.st_mode)) return "a directory, not a PEM file: name the file in it";
  if (::access(path.c_str(), R_OK) != 0)
    return fmt::format("not readable by user {}, who runs this ({}): the daemon's user must be able to read it, e.g. "
                       "chgrp unima-bridge FILE; chmod 640 FILE",
                       this_user(), std::strerror(errno));
  return std::nullopt;
}

X509Ptr first_certificate(const std::string& path) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "r"));
  if (!file) return nullptr;
  X509Ptr certificate(PEM_read_X509(file.get(), nullptr, nullptr, nullptr));
  ERR_clear_error();
  return certificate;
}

// Never asks for a passphrase: the daemon cannot type one.
int no_passphrase(char*, int, int, void*) { return -1; }

KeyPtr private_key(const std::string& path) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "r"));
  if (!file) return nullptr;
  KeyPtr key(PEM_read_PrivateKey(file.get(), nullptr, no_passphrase, nullptr));
  ERR_clear_error();
  return key;
}

bool holds(const std::string& text, const char* label) { return text.find(label) != std::string::npos; }

std::string date_text(const ASN1_TIME* time) {
  std::tm tm{};
  if (ASN1_TIME_to_tm(time, &tm) != 1) return "?";
  return fmt::format("{:04}-{:02}-{:02}", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday);
}

}  // namespace

std::optional<std::string> pem_file_problem(const std::string& path, PemContent content) {
  if (auto problem = unopenable(path)) return problem;
  const auto text = text_of(path);
  const bool has_key = holds(text, "PRIVATE KEY-----");
  const bool has_certificate = holds(text, "-----BEGIN CERTIFICATE-----");
  if (content == PemContent::private_key) {
    if (private_key(path)) return std::nullopt;
    if (holds(text, "-----BEGIN ENCRYPTED PRIVATE KEY-----") || holds(text, "Proc-Type: 4,ENCRYPTED"))
      return "a private key encrypted with a passphrase, which the daemon cannot type: store it without one "
             "(openssl pkey -in FILE -out NEW), readable by the daemon's user only";
    if (has_certificate && !has_key)
      return "a certificate, not a private key: are the certificate and key files swapped?";
    return "not a PEM private key (-----BEGIN PRIVATE KEY----- …) that OpenSSL can read: give the key the "
           "certificate was made for";
  }
  if (first_certificate(path)) return std::nullopt;
  if (has_key && !has_certificate)
    return "a private key, not a certificate: are the certificate and key files swapped?";
  return fmt::format("not a PEM certificate (-----BEGIN CERTIFICATE----- …) that OpenSSL can read: give {}",
                     content == PemContent::certificate ? "the server's certificate, with its chain"
                                                        : "the CA certificate(s) that signed the peers' certificates");
}

std::optional<std::string> key_mismatch(const std::string& certificate_path, const std::string& key_path,
                                        std::string_view certificate_name) {
  const auto certificate = first_certificate(certificate_path);
  const auto key = private_key(key_path);
  if (!certificate || !key) return std::nullopt;  // pem_file_problem's to say
  const bool matches = X509_check_private_key(certificate.get(), key.get()) == 1;
  ERR_clear_error();
  if (matches) return std::nullopt;
  return fmt::format("this key does not belong to the certificate of {} ({}): give the key the certificate was made "
                     "for, or the certificate made for this key",
                     certificate_name, certificate_path);
}

std::optional<std::string> certificate_out_of_date(const std::string& path, std::time_t now) {
  const auto certificate = first_certificate(path);
  if (!certificate) return std::nullopt;
  const auto* not_after = X509_get0_notAfter(certificate.get());
  const auto* not_before = X509_get0_notBefore(certificate.get());
  if (X509_cmp_time(not_after, &now) < 0)
    return fmt::format("the certificate expired on {}: peers refuse it; renew it (a reload takes the new one)",
                       date_text(not_after));
  if (X509_cmp_time(not_before, &now) > 0)
    return fmt::format("the certificate is valid only from {}: peers refuse it until then; is this machine's clock "
                       "right?",
                       date_text(not_before));
  return std::nullopt;
}

}  // namespace unima::tls
