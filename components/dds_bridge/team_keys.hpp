#pragma once

// Team keys for DDS-Security (docs/security.md): a team's certificate authority, one identity
// certificate per place (a robot, the ground station, the simulator), the governance document
// and each place's permissions, signed by the authority. Fast DDS's builtin plugins use them:
// PKI-DH authentication, Access-Permissions, AES-GCM-GMAC (every RTPS message encrypted).
//
// A key folder holds
//   ca.pem, ca.key                 the team's authority (P-256, self-signed; keep ca.key safe)
//   governance.xml, governance.p7s the domain's rules, signed (S/MIME, as Fast DDS reads them)
//   <place>.pem, <place>.key       a place's identity, signed by the authority
//   permissions_<place>.xml/.p7s   what the place may publish and read, signed
// where <place> is robot_<id>, station or sim (place_name()).

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/result.hpp"

namespace scancrew::dds_bridge {

// A place's name in a key folder: "robot_<id>", "station" (bridge id 0) or "sim" (the
// simulator's bridge id).
std::string place_name(uint32_t bridge_id, uint32_t simulator_id);

// The certificate subject of a place of a team: "CN=<place>,O=scancrew <team>".
std::string place_subject(const std::string& team, const std::string& place);

// The first six bytes of the GUID prefix of every participant that authenticates with a
// place's certificate: PKI-DH derives them from the SHA-256 of the certificate's subject
// (DDS-Security 1.1, 9.3.3), and the handshake refuses a participant whose prefix does not
// match its certificate. So a participant's prefix names the place it authenticated as.
std::array<uint8_t, 6> place_guid_prefix(const std::string& team, const std::string& place);

// What a place may do: publish (write) and subscribe (read) these DDS topic names (fnmatch
// patterns), on these domains.
struct PlaceGrant {
  std::string place;
  std::vector<std::string> publish, subscribe;
  uint32_t domain_min = 0, domain_max = 232;
};

// Creates a team's authority and its governance in `dir` (made if absent). Refuses a folder
// that already holds ca.key (a second authority would orphan the places' certificates).
Result<void, std::string> init_team_keys(const std::string& dir, const std::string& team);

// Adds (or replaces) a place's identity and permissions in a folder made by init_team_keys.
Result<void, std::string> add_place_keys(const std::string& dir, const PlaceGrant& grant);

// The team name recorded by init_team_keys (the authority's organisation).
Result<std::string, std::string> team_of_keys(const std::string& dir);

// The Fast DDS participant properties that make a place's participant secure: the plugins
// and file: URIs of its certificate, key, governance and permissions. Checks the files exist.
Result<std::vector<std::pair<std::string, std::string>>, std::string> security_properties(
    const std::string& dir, const std::string& place);

}  // namespace scancrew::dds_bridge
