#include "components/dds_bridge/team_keys.hpp"

#include <fcntl.h>
#include <openssl/bio.h>
#include <openssl/bn.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/pkcs7.h>
#include <openssl/rand.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "core/markup_escape.hpp"

namespace scancrew::dds_bridge {
namespace {

namespace fs = std::filesystem;

template <class T, void (*Free)(T*)>
struct Deleter {
  void operator()(T* p) const { Free(p); }
};
using Key = std::unique_ptr<EVP_PKEY, Deleter<EVP_PKEY, EVP_PKEY_free>>;
using Cert = std::unique_ptr<X509, Deleter<X509, X509_free>>;
using Bio = std::unique_ptr<BIO, Deleter<BIO, BIO_free_all>>;
using Pkcs7 = std::unique_ptr<PKCS7, Deleter<PKCS7, PKCS7_free>>;
using Name = std::unique_ptr<X509_NAME, Deleter<X509_NAME, X509_NAME_free>>;

constexpr long kValidDays = 3650;  // certificates and permissions: ten years from creation
constexpr const char* kXsiHeader =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    "<dds xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\"";

std::string openssl_error(const std::string& what) {
  std::string out = what;
  if (const unsigned long e = ERR_get_error(); e != 0) {
    char buf[256];
    ERR_error_string_n(e, buf, sizeof buf);
    out += " (" + std::string(buf) + ")";
  }
  ERR_clear_error();
  return out;
}

// Writes a new file (an existing one is replaced): a secret one is created 0600, exclusively
// and without following a link, so that no other user can open it before the key is in it.
Result<void, std::string> write_file(const fs::path& path, const std::string& text, bool secret) {
  std::error_code ec;
  fs::remove(path, ec);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC,
                        secret ? 0600 : 0644);
  if (fd < 0)
    return make_unexpected("cannot write " + path.string() + ": " +
                           std::error_code(errno, std::generic_category()).message());
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n <= 0) {
      ::close(fd);
      return make_unexpected("cannot write " + path.string() + ": " +
                             std::error_code(errno, std::generic_category()).message());
    }
    done += static_cast<size_t>(n);
  }
  if (::close(fd) != 0)
    return make_unexpected("cannot write " + path.string() + ": " +
                           std::error_code(errno, std::generic_category()).message());
  return {};
}

Result<std::string, std::string> read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_unexpected("cannot read " + path.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

Result<std::string, std::string> bio_text(BIO* bio) {
  char* data = nullptr;
  const long n = BIO_get_mem_data(bio, &data);
  if (n <= 0 || data == nullptr) return make_unexpected(openssl_error("OpenSSL wrote nothing"));
  return std::string(data, static_cast<size_t>(n));
}

Result<Key, std::string> new_key() {
  Key key(EVP_EC_gen("P-256"));
  if (!key) return make_unexpected(openssl_error("cannot make a P-256 key"));
  return key;
}

// The subject O=org, CN=cn (in that order: its RFC 2253 form, which the permissions' subject
// names, reads "CN=cn,O=org"); null if OpenSSL fails.
Name make_name(const std::string& cn, const std::string& org) {
  Name name(X509_NAME_new());
  const auto* cn_bytes = reinterpret_cast<const unsigned char*>(cn.c_str());
  const auto* org_bytes = reinterpret_cast<const unsigned char*>(org.c_str());
  if (!name ||
      X509_NAME_add_entry_by_txt(name.get(), "O", MBSTRING_UTF8, org_bytes, -1, -1, 0) != 1 ||
      X509_NAME_add_entry_by_txt(name.get(), "CN", MBSTRING_UTF8, cn_bytes, -1, -1, 0) != 1)
    return nullptr;
  return name;
}

Result<void, std::string> add_extension(X509* cert, X509* issuer, int nid, const char* value) {
  X509V3_CTX ctx;
  X509V3_set_ctx_nodb(&ctx);
  X509V3_set_ctx(&ctx, issuer, cert, nullptr, nullptr, 0);
  X509_EXTENSION* ext = X509V3_EXT_conf_nid(nullptr, &ctx, nid, value);
  if (ext == nullptr) return make_unexpected(openssl_error("cannot make a certificate extension"));
  const int ok = X509_add_ext(cert, ext, -1);
  X509_EXTENSION_free(ext);
  if (ok != 1) return make_unexpected(openssl_error("cannot add a certificate extension"));
  return {};
}

// A certificate for `key` with subject CN=cn,O=org, signed by issuer_key (self-signed when
// issuer is null), serial from the clock.
Result<Cert, std::string> make_cert(EVP_PKEY* key, const std::string& cn, const std::string& org,
                                    X509* issuer, EVP_PKEY* issuer_key, bool ca) {
  Cert cert(X509_new());
  if (!cert) return make_unexpected(openssl_error("cannot make a certificate"));
  if (X509_set_version(cert.get(), 2) != 1)
    return make_unexpected(openssl_error("cannot set the certificate's version"));
  // a random serial: certificates made in the same second stay distinct
  unsigned char serial[8];
  if (RAND_bytes(serial, sizeof serial) != 1)
    return make_unexpected(openssl_error("cannot draw a serial number"));
  serial[0] &= 0x7f;
  BIGNUM* bn = BN_bin2bn(serial, sizeof serial, nullptr);
  const bool serial_set =
      bn != nullptr && BN_to_ASN1_INTEGER(bn, X509_get_serialNumber(cert.get())) != nullptr;
  BN_free(bn);
  if (!serial_set) return make_unexpected(openssl_error("cannot set the serial number"));
  if (X509_gmtime_adj(X509_getm_notBefore(cert.get()), -3600) == nullptr ||  // clock skew
      X509_gmtime_adj(X509_getm_notAfter(cert.get()), kValidDays * 24 * 3600) == nullptr)
    return make_unexpected(openssl_error("cannot set the validity"));
  const Name name = make_name(cn, org);
  if (!name || X509_set_subject_name(cert.get(), name.get()) != 1)
    return make_unexpected(openssl_error("cannot set the subject"));
  X509_set_issuer_name(cert.get(), issuer != nullptr ? X509_get_subject_name(issuer) : name.get());
  X509_set_pubkey(cert.get(), key);
  X509* issuer_cert = issuer != nullptr ? issuer : cert.get();
  if (ca) {
    if (auto r = add_extension(cert.get(), issuer_cert, NID_basic_constraints, "critical,CA:TRUE");
        !r)
      return make_unexpected(r.error());
    // digitalSignature too: the authority signs the governance and permissions documents
    if (auto r = add_extension(cert.get(), issuer_cert, NID_key_usage,
                               "critical,digitalSignature,keyCertSign,cRLSign");
        !r)
      return make_unexpected(r.error());
  } else {
    if (auto r = add_extension(cert.get(), issuer_cert, NID_basic_constraints, "critical,CA:FALSE");
        !r)
      return make_unexpected(r.error());
    if (auto r = add_extension(cert.get(), issuer_cert, NID_key_usage,
                               "critical,digitalSignature,keyAgreement");
        !r)
      return make_unexpected(r.error());
  }
  if (X509_sign(cert.get(), issuer_key != nullptr ? issuer_key : key, EVP_sha256()) <= 0)
    return make_unexpected(openssl_error("cannot sign the certificate"));
  return cert;
}

Result<void, std::string> write_key(const fs::path& path, EVP_PKEY* key) {
  Bio bio(BIO_new(BIO_s_mem()));
  if (!bio || PEM_write_bio_PrivateKey(bio.get(), key, nullptr, nullptr, 0, nullptr, nullptr) != 1)
    return make_unexpected(openssl_error("cannot encode the key"));
  auto text = bio_text(bio.get());
  if (!text) return make_unexpected(text.error());
  return write_file(path, *text, true);
}

Result<void, std::string> write_cert(const fs::path& path, X509* cert) {
  Bio bio(BIO_new(BIO_s_mem()));
  if (!bio || PEM_write_bio_X509(bio.get(), cert) != 1)
    return make_unexpected(openssl_error("cannot encode the certificate"));
  auto text = bio_text(bio.get());
  if (!text) return make_unexpected(text.error());
  return write_file(path, *text, false);
}

Result<Key, std::string> read_key(const fs::path& path) {
  auto text = read_file(path);
  if (!text) return make_unexpected(text.error());
  Bio bio(BIO_new_mem_buf(text->data(), static_cast<int>(text->size())));
  Key key(PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr));
  if (!key) return make_unexpected(openssl_error(path.string() + ": not a PEM private key"));
  return key;
}

Result<Cert, std::string> read_cert(const fs::path& path) {
  auto text = read_file(path);
  if (!text) return make_unexpected(text.error());
  Bio bio(BIO_new_mem_buf(text->data(), static_cast<int>(text->size())));
  Cert cert(PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr));
  if (!cert) return make_unexpected(openssl_error(path.string() + ": not a PEM certificate"));
  return cert;
}

// The document signed by the authority as S/MIME (text, detached signature): what
// `openssl smime -sign -text` writes and Fast DDS's Access-Permissions plugin reads.
Result<void, std::string> write_signed(const fs::path& path, const std::string& document, X509* ca,
                                       EVP_PKEY* ca_key) {
  Bio in(BIO_new_mem_buf(document.data(), static_cast<int>(document.size())));
  const int flags = PKCS7_TEXT | PKCS7_DETACHED;
  Pkcs7 p7(PKCS7_sign(ca, ca_key, nullptr, in.get(), flags));
  if (!p7) return make_unexpected(openssl_error("cannot sign " + path.string()));
  Bio out(BIO_new(BIO_s_mem()));
  Bio again(BIO_new_mem_buf(document.data(), static_cast<int>(document.size())));
  if (SMIME_write_PKCS7(out.get(), p7.get(), again.get(), flags) != 1)
    return make_unexpected(openssl_error("cannot encode " + path.string()));
  auto text = bio_text(out.get());
  if (!text) return make_unexpected(text.error());
  return write_file(path, *text, false);
}

std::string iso_date(long days_from_now) {
  const time_t t = time(nullptr) + days_from_now * 24 * 3600;
  struct tm tm {};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  return buf;
}

std::string governance_xml() {
  // every domain: only the team's authenticated places join; discovery, liveliness and each
  // RTPS message encrypted; every topic read and written under access control
  std::string x = kXsiHeader;
  x +=
      R"( xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>232</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>ENCRYPT</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
)";
  return x;
}

std::string topics_xml(const std::vector<std::string>& topics) {
  std::string x = "<topics>";
  for (const std::string& t : topics) x += "<topic>" + markup_escape(t) + "</topic>";
  return x + "</topics>";
}

std::string permissions_xml(const std::string& subject, const PlaceGrant& g) {
  std::string x = kXsiHeader;
  x +=
      R"( xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name=")" +
      markup_escape(g.place) + R"(">
      <subject_name>)" +
      markup_escape(subject) + R"(</subject_name>
      <validity><not_before>)" +
      iso_date(-1) + "</not_before><not_after>" + iso_date(kValidDays) + R"(</not_after></validity>
      <allow_rule>
        <domains><id_range><min>)" +
      std::to_string(g.domain_min) + "</min><max>" + std::to_string(g.domain_max) +
      R"(</max></id_range></domains>
)";
  // a rule without <partitions> holds for the default partition only; the bridges write in
  // the team's partitions, so every partition is allowed (the topics are what is restricted)
  if (!g.publish.empty())
    x += "        <publish>" + topics_xml(g.publish) +
         "<partitions><partition>*</partition></partitions></publish>\n";
  if (!g.subscribe.empty())
    x += "        <subscribe>" + topics_xml(g.subscribe) +
         "<partitions><partition>*</partition></partitions></subscribe>\n";
  x += R"(      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
)";
  return x;
}

bool valid_place(const std::string& place) {
  if (place.empty() || place.size() > 64) return false;
  for (const char c : place)
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return false;
  return true;
}

}  // namespace

std::string place_name(uint32_t bridge_id, uint32_t simulator_id) {
  if (bridge_id == simulator_id) return "sim";
  if (bridge_id == 0) return "station";
  return "robot_" + std::to_string(bridge_id);
}

std::string place_subject(const std::string& team, const std::string& place) {
  return "CN=" + place + ",O=scancrew " + team;
}

std::array<uint8_t, 6> place_guid_prefix(const std::string& team, const std::string& place) {
  std::array<uint8_t, 6> prefix{};
  const Name name = make_name(place, "scancrew " + team);
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (!name || X509_NAME_digest(name.get(), EVP_sha256(), md, &length) != 1 || length < 6)
    return prefix;  // all zero: matches no authenticated participant (0x80 is always set)
  // 0x80, then the digest's first 47 bits (DDS-Security 1.1, 9.3.3; Fast DDS PKIDH.cpp)
  prefix[0] = static_cast<uint8_t>(0x80 | (md[0] >> 1));
  for (size_t i = 1; i < 6; ++i) prefix[i] = static_cast<uint8_t>((md[i - 1] << 7) | (md[i] >> 1));
  return prefix;
}

Result<void, std::string> init_team_keys(const std::string& dir, const std::string& team) {
  if (team.empty() || team.size() > 48 || team.find_first_of(",=+<>#;\"\\/") != std::string::npos)
    return make_unexpected("team name '" + team +
                           "': 1 to 48 characters, none of , = + < > # ; \" \\ /");
  const fs::path d(dir);
  std::error_code ec;
  fs::create_directories(d, ec);
  if (ec) return make_unexpected("cannot make " + dir + ": " + ec.message());
  if (fs::exists(d / "ca.key"))
    return make_unexpected(dir + " already holds a team authority (ca.key); a new one would " +
                           "orphan every place's certificate: use another folder");
  auto key = new_key();
  if (!key) return make_unexpected(key.error());
  auto ca = make_cert(key->get(), "scancrew " + team + " authority", "scancrew " + team, nullptr,
                      nullptr, true);
  if (!ca) return make_unexpected(ca.error());
  for (auto r : {write_key(d / "ca.key", key->get()), write_cert(d / "ca.pem", ca->get())})
    if (!r) return r;
  const std::string governance = governance_xml();
  if (auto r = write_file(d / "governance.xml", governance, false); !r) return r;
  return write_signed(d / "governance.p7s", governance, ca->get(), key->get());
}

Result<std::string, std::string> team_of_keys(const std::string& dir) {
  auto ca = read_cert(fs::path(dir) / "ca.pem");
  if (!ca) return make_unexpected(ca.error());
  X509_NAME* name = X509_get_subject_name(ca->get());
  const int at = X509_NAME_get_index_by_NID(name, NID_organizationName, -1);
  if (at < 0) return make_unexpected(dir + "/ca.pem: no organisation in its subject");
  const ASN1_STRING* s = X509_NAME_ENTRY_get_data(X509_NAME_get_entry(name, at));
  std::string org(reinterpret_cast<const char*>(ASN1_STRING_get0_data(s)),
                  static_cast<size_t>(ASN1_STRING_length(s)));
  const std::string prefix = "scancrew ";
  if (org.rfind(prefix, 0) != 0)
    return make_unexpected(dir + "/ca.pem: not a scancrew team authority (" + org + ")");
  return org.substr(prefix.size());
}

Result<void, std::string> add_place_keys(const std::string& dir, const PlaceGrant& grant) {
  if (!valid_place(grant.place))
    return make_unexpected("place name '" + grant.place + "': lower-case letters, digits, '_'");
  const fs::path d(dir);
  auto team = team_of_keys(dir);
  if (!team) return make_unexpected(team.error() + " (make the folder with `scancrew keys init`)");
  auto ca_key = read_key(d / "ca.key");
  if (!ca_key) return make_unexpected(ca_key.error());
  auto ca = read_cert(d / "ca.pem");
  if (!ca) return make_unexpected(ca.error());
  if (X509_check_private_key(ca->get(), ca_key->get()) != 1)
    return make_unexpected(dir + ": ca.key is not the key of ca.pem");
  auto key = new_key();
  if (!key) return make_unexpected(key.error());
  auto cert =
      make_cert(key->get(), grant.place, "scancrew " + *team, ca->get(), ca_key->get(), false);
  if (!cert) return make_unexpected(cert.error());
  for (auto r : {write_key(d / (grant.place + ".key"), key->get()),
                 write_cert(d / (grant.place + ".pem"), cert->get())})
    if (!r) return r;
  const std::string permissions = permissions_xml(place_subject(*team, grant.place), grant);
  const fs::path xml = d / ("permissions_" + grant.place + ".xml");
  if (auto r = write_file(xml, permissions, false); !r) return r;
  return write_signed(d / ("permissions_" + grant.place + ".p7s"), permissions, ca->get(),
                      ca_key->get());
}

Result<std::vector<std::pair<std::string, std::string>>, std::string> security_properties(
    const std::string& dir, const std::string& place) {
  const fs::path d = fs::absolute(fs::path(dir));
  const fs::path files[] = {d / "ca.pem", d / (place + ".pem"), d / (place + ".key"),
                            d / "governance.p7s", d / ("permissions_" + place + ".p7s")};
  for (const fs::path& f : files)
    if (!fs::is_regular_file(f))
      return make_unexpected("security: " + f.string() + " is missing (`scancrew keys add " + dir +
                             " ...` makes a place's files)");
  auto uri = [](const fs::path& p) { return "file://" + p.string(); };  // file:///abs/path
  const std::string auth = "dds.sec.auth.builtin.PKI-DH.";
  const std::string access = "dds.sec.access.builtin.Access-Permissions.";
  return std::vector<std::pair<std::string, std::string>>{
      {"dds.sec.auth.plugin", "builtin.PKI-DH"},
      {auth + "identity_ca", uri(files[0])},
      {auth + "identity_certificate", uri(files[1])},
      {auth + "private_key", uri(files[2])},
      {"dds.sec.access.plugin", "builtin.Access-Permissions"},
      {access + "permissions_ca", uri(files[0])},
      {access + "governance", uri(files[3])},
      {access + "permissions", uri(files[4])},
      {"dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC"},
  };
}

}  // namespace scancrew::dds_bridge
