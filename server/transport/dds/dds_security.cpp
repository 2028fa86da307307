#include "transport/dds/dds_security.hpp"

#include <openssl/bio.h>
#include <openssl/objects.h>
#include <openssl/pem.h>
#include <openssl/x509.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>

#include "transport/transport.hpp"

#ifndef RIGID_DDS_SECURITY_DIR
#error "RIGID_DDS_SECURITY_DIR: the directory of Cyclone's security plugins (set by CMake)"
#endif

namespace rigid::transport::dds {
namespace {

constexpr std::array kFiles{"identity_ca.pem", "permissions_ca.pem", "governance.p7s", "cert.pem",
                            "key.pem",         "permissions.p7s",    "crl.pem"};

std::string plugin(std::string_view name) {
  return std::string(RIGID_DDS_SECURITY_DIR) + "/libdds_security_" + std::string(name) + ".so";
}

std::string common_name(const std::string& cert_path) {
  const std::unique_ptr<BIO, decltype(&BIO_free)> bio(BIO_new_file(cert_path.c_str(), "r"),
                                                      &BIO_free);
  if (!bio) throw TransportError("DDS Security: cannot read " + cert_path);
  const std::unique_ptr<X509, decltype(&X509_free)> cert(
      PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr), &X509_free);
  if (!cert) {
    throw TransportError("DDS Security: " + cert_path +
                         " is not a PEM certificate (make identities with rigid-keys add)");
  }
  std::array<char, 256> cn{};
  const int n = X509_NAME_get_text_by_NID(X509_get_subject_name(cert.get()), NID_commonName,
                                          cn.data(), static_cast<int>(cn.size()));
  if (n <= 0) throw TransportError("DDS Security: " + cert_path + " has no common name (CN)");
  return std::string(cn.data(), static_cast<std::size_t>(n));
}

}  // namespace

Identity load_identity(const std::string& directory) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path dir = fs::absolute(directory, error);
  if (error || !fs::is_directory(dir)) {
    throw TransportError(
        "--security " + directory +
        ": not a directory (make one with: rigid-keys add KEYSTORE NAME --may ...)");
  }
  for (const char* file : kFiles) {
    const fs::path p = dir / file;
    if (::access(p.c_str(), R_OK) != 0) {
      throw TransportError("--security " + directory + ": cannot read " + file + " (" +
                           std::strerror(errno) +
                           "); an identity directory made by rigid-keys "
                           "add holds " +
                           "identity_ca.pem, permissions_ca.pem, governance.p7s, "
                           "cert.pem, key.pem, permissions.p7s and crl.pem");
    }
  }
  Identity identity;
  identity.directory = fs::weakly_canonical(dir).string();
  identity.name = common_name(identity.directory + "/cert.pem");
  if (identity.name.find('/') != std::string::npos || identity.name.empty()) {
    throw TransportError("DDS Security: identity name '" + identity.name +
                         "' in cert.pem is not a rigid-keys name");
  }
  return identity;
}

Qos participant_security_qos(const Identity& identity) {
  Qos qos(dds_create_qos());
  const auto file = [&identity](const char* name) {
    return "file:" + identity.directory + "/" + name;
  };
  const auto set = [&qos](const char* key, const std::string& value) {
    dds_qset_prop(qos.get(), key, value.c_str());
  };
  set("dds.sec.auth.library.path", plugin("auth"));
  set("dds.sec.auth.library.init", "init_authentication");
  set("dds.sec.auth.library.finalize", "finalize_authentication");
  set("dds.sec.crypto.library.path", plugin("crypto"));
  set("dds.sec.crypto.library.init", "init_crypto");
  set("dds.sec.crypto.library.finalize", "finalize_crypto");
  set("dds.sec.access.library.path", plugin("ac"));
  set("dds.sec.access.library.init", "init_access_control");
  set("dds.sec.access.library.finalize", "finalize_access_control");
  set("dds.sec.auth.identity_ca", file("identity_ca.pem"));
  set("dds.sec.auth.identity_certificate", file("cert.pem"));
  set("dds.sec.auth.private_key", file("key.pem"));
  set("org.eclipse.cyclonedds.sec.auth.crl", file("crl.pem"));
  set("dds.sec.access.permissions_ca", file("permissions_ca.pem"));
  set("dds.sec.access.governance", file("governance.p7s"));
  set("dds.sec.access.permissions", file("permissions.p7s"));
  return qos;
}

std::string push_partition(std::string_view identity, std::string_view body) {
  std::string p(kPushPartition);
  p += '/';
  p += identity;
  p += '/';
  p += body;
  return p;
}

std::string control_partition(std::string_view identity) {
  std::string p(kControlPartition);
  p += '/';
  p += identity;
  return p;
}

}  // namespace rigid::transport::dds
