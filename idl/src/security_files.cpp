#include "fleet_transport/security.hpp"

#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/pkcs7.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>

#include <filesystem>
#include <memory>
#include <stdexcept>

namespace fleet_transport {

namespace {

namespace fs = std::filesystem;

std::string required_file(const fs::path& path, const std::string& made_by) {
  if (!fs::exists(path)) {
    throw std::invalid_argument("security: " + path.string() + " is missing (made by: " + made_by + ")");
  }
  // Certificates, keys and signed documents are a few kilobytes: anything else is not one of them.
  constexpr std::uintmax_t kLargest = 1 << 20;
  if (!fs::is_regular_file(path) || fs::file_size(path) > kLargest) {
    throw std::invalid_argument("security: " + path.string() + " is not a regular file of at most 1 MiB");
  }
  return fs::absolute(path).string();
}

template <typename T, void (*Free)(T*)>
struct Deleter {
  void operator()(T* p) const { Free(p); }
};
using Bio = std::unique_ptr<BIO, Deleter<BIO, BIO_free_all>>;
using Certificate = std::unique_ptr<X509, Deleter<X509, X509_free>>;
using Key = std::unique_ptr<EVP_PKEY, Deleter<EVP_PKEY, EVP_PKEY_free>>;
using Store = std::unique_ptr<X509_STORE, Deleter<X509_STORE, X509_STORE_free>>;
using StoreContext = std::unique_ptr<X509_STORE_CTX, Deleter<X509_STORE_CTX, X509_STORE_CTX_free>>;
using Pkcs7 = std::unique_ptr<PKCS7, Deleter<PKCS7, PKCS7_free>>;

std::string openssl_reason() {
  const unsigned long code = ERR_get_error();
  ERR_clear_error();
  if (code == 0) return "unreadable";
  char text[256];
  ERR_error_string_n(code, text, sizeof text);
  return text;
}

Bio open(const std::string& path) {
  Bio bio(BIO_new_file(path.c_str(), "r"));
  if (!bio) throw std::invalid_argument("security: cannot open " + path);
  return bio;
}

Certificate read_certificate(const std::string& path) {
  Certificate certificate(PEM_read_bio_X509(open(path).get(), nullptr, nullptr, nullptr));
  if (!certificate) throw std::invalid_argument("security: " + path + " is not a PEM certificate (" + openssl_reason() + ")");
  return certificate;
}

Store trusting(const std::string& ca_path) {
  Store store(X509_STORE_new());
  if (!store || X509_STORE_add_cert(store.get(), read_certificate(ca_path).get()) != 1) {
    throw std::invalid_argument("security: cannot use " + ca_path + " as a CA (" + openssl_reason() + ")");
  }
  return store;
}

std::string common_name(X509* certificate) {
  char name[256] = {0};
  if (X509_NAME_get_text_by_NID(X509_get_subject_name(certificate), NID_commonName, name, sizeof name) < 0) return "";
  return name;
}

void check_certificate(const SecurityFiles& files) {
  const Certificate certificate = read_certificate(files.identity_certificate);
  const Store store = trusting(files.identity_ca);
  if (!files.revocation_list.empty()) {
    using Crl = std::unique_ptr<X509_CRL, Deleter<X509_CRL, X509_CRL_free>>;
    const Crl crl(PEM_read_bio_X509_CRL(open(files.revocation_list).get(), nullptr, nullptr, nullptr));
    if (!crl || X509_STORE_add_crl(store.get(), crl.get()) != 1) {
      throw std::invalid_argument("security: " + files.revocation_list + " is not a PEM revocation list (" + openssl_reason() + ")");
    }
    X509_STORE_set_flags(store.get(), X509_V_FLAG_CRL_CHECK);
  }
  const StoreContext context(X509_STORE_CTX_new());
  if (!context || X509_STORE_CTX_init(context.get(), store.get(), certificate.get(), nullptr) != 1) {
    throw std::invalid_argument("security: cannot check " + files.identity_certificate);
  }
  if (X509_verify_cert(context.get()) != 1) {
    throw std::invalid_argument("security: " + files.identity_certificate + " is refused: " +
                             X509_verify_cert_error_string(X509_STORE_CTX_get_error(context.get())) +
                             " (checked against " + files.identity_ca + ")");
  }
  if (const std::string name = common_name(certificate.get()); name != files.participant) {
    throw std::invalid_argument("security: " + files.identity_certificate + " is the identity of '" + name + "', not of '" +
                             files.participant + "'");
  }
  const Key key(PEM_read_bio_PrivateKey(open(files.private_key).get(), nullptr, nullptr, nullptr));
  if (!key) throw std::invalid_argument("security: " + files.private_key + " is not a PEM private key (" + openssl_reason() + ")");
  if (X509_check_private_key(certificate.get(), key.get()) != 1) {
    ERR_clear_error();
    throw std::invalid_argument("security: " + files.private_key + " does not belong to " + files.identity_certificate);
  }
}

void check_signed_document(const std::string& path, const std::string& permissions_ca) {
  BIO* content = nullptr;
  const Pkcs7 document(SMIME_read_PKCS7(open(path).get(), &content));
  const Bio content_owner(content);
  if (!document) throw std::invalid_argument("security: " + path + " is not a signed (S/MIME) document (" + openssl_reason() + ")");
  const Store store = trusting(permissions_ca);
  const Bio discard(BIO_new(BIO_s_null()));
  if (PKCS7_verify(document.get(), nullptr, store.get(), content, discard.get(), PKCS7_TEXT) != 1) {
    throw std::invalid_argument("security: " + path + " is refused: its signature does not verify against " + permissions_ca +
                             " (changed after signing, or signed by another fleet's CA: " + openssl_reason() + ")");
  }
}

}  // namespace

SecurityFiles fleet_security_files(const std::string& fleet_dir, const std::string& name) {
  const fs::path dir(fleet_dir);
  if (!fs::is_directory(dir)) {
    throw std::invalid_argument("security: fleet directory " + fleet_dir + " does not exist (made by: ctsfleet-ca init " +
                             fleet_dir + ")");
  }
  const fs::path own = dir / "participants" / name;
  const std::string enrol = "ctsfleet-ca add-robot " + fleet_dir + " " + name + " (or add-coordinator / add-observer)";
  SecurityFiles files;
  files.participant = name;
  files.identity_ca = required_file(dir / "identity_ca.pem", "ctsfleet-ca init " + fleet_dir);
  files.permissions_ca = required_file(dir / "permissions_ca.pem", "ctsfleet-ca init " + fleet_dir);
  files.governance = required_file(dir / "governance.p7s", "ctsfleet-ca init " + fleet_dir);
  files.identity_certificate = required_file(own / "cert.pem", enrol);
  files.private_key = required_file(own / "key.pem", enrol);
  files.permissions = required_file(own / "permissions.p7s", enrol);
  if (fs::is_regular_file(dir / "crl.pem")) files.revocation_list = fs::absolute(dir / "crl.pem").string();
  return files;
}

void check_security_files(const SecurityFiles& files) {
  check_certificate(files);
  check_signed_document(files.governance, files.permissions_ca);
  check_signed_document(files.permissions, files.permissions_ca);
}

SecurityFiles load_fleet_security(const std::string& fleet_dir, const std::string& name) {
  if (fleet_dir.empty()) return {};
  SecurityFiles files = fleet_security_files(fleet_dir, name);
  check_security_files(files);
  return files;
}

}  // namespace fleet_transport
