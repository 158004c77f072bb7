// DDS Security for the fleet: which files a participant presents (made by scripts/fleet-ca), and
// the checks run on them before the middleware sees them, so that an operator reads "robot3's
// certificate expired on ..." instead of a participant that silently never appears.
#pragma once

#include <string>

namespace fleet_transport {

// The files of one participant, as absolute paths. Both vendors' builtin plugins read them:
// authentication PKI-DH, access control Permissions, cryptography AES-GCM-GMAC.
struct SecurityFiles {
  std::string identity_ca;           // signs every participant's certificate
  std::string identity_certificate;  // this participant's; its subject carries its name
  std::string private_key;
  std::string permissions_ca;        // signs the governance and every permissions document
  std::string governance;            // the domain's rules (governance.p7s)
  std::string permissions;           // what this participant may publish and subscribe (permissions.p7s)
  std::string revocation_list;       // crl.pem; read by Cyclone DDS only ("" when absent)
  std::string participant;           // the enrolled name (robot id, coordinator or observer name)
  bool enabled() const { return !identity_certificate.empty(); }
};

// The files of participant `name` in fleet directory `fleet_dir`. Throws std::invalid_argument that
// names the missing or bad file and the fleet-ca command that makes it.
SecurityFiles fleet_security_files(const std::string& fleet_dir, const std::string& name);

// Checks with OpenSSL what the plugins would refuse later without a word: the certificate is
// signed by the fleet's identity CA, is valid now and names `files.participant`; the key matches
// it; it is not on the fleet's revocation list; governance and permissions carry a valid
// signature of the permissions CA. Throws std::invalid_argument naming the file and the reason.
void check_security_files(const SecurityFiles& files);

// Both of the above; security off (no files) when `fleet_dir` is empty.
SecurityFiles load_fleet_security(const std::string& fleet_dir, const std::string& name);

// The command that makes a fleet directory, for error messages.
inline constexpr const char* kFleetCaHint = "make one with `ctsfleet-ca init DIR`, then `ctsfleet-ca add-robot DIR ID` "
                                            "per robot and `ctsfleet-ca add-coordinator DIR coordinator`";

}  // namespace fleet_transport
