// How DDS Security binds a participant's GUID to its certificate.
//
// PKI-DH (OMG DDS-Security 1.1, 9.3.3; Fast DDS 2.9 PKIDH adjust_participant_key) makes the
// first 48 bits of a secure participant's GUID prefix a 1 bit followed by the first 47 bits of
// SHA-256(subject name of its certificate, DER), and the handshake refuses a peer whose GUID in
// the handshake's participant data does not derive from the certificate it authenticated with.
// So once a participant is authenticated, its GUID prefix tells which certificate subject it
// holds (given the subjects a CA issued; 47 bits are no defence against chosen subjects, so the
// subject must come from a certificate the identity CA signed). Pure.
#pragma once

#include <array>
#include <cstdint>

namespace mostar::identity {

using GuidPrefix = std::array<uint8_t, 12>;  // RTPS GUID prefix of a participant
using Sha256 = std::array<uint8_t, 32>;

// The GUID prefix bits PKI-DH derives from `subject_hash`: byte 0 bit 7 set, then the first 47
// bits of the hash; the other bits of `candidate` are kept.
GuidPrefix AdjustGuidPrefix(const GuidPrefix& candidate, const Sha256& subject_hash);

// True when `prefix` is a PKI-DH prefix derived from `subject_hash` (the check the handshake
// makes): leading bit set and the next 47 bits equal to the first 47 bits of the hash.
bool GuidPrefixDerivesFromSubject(const GuidPrefix& prefix, const Sha256& subject_hash);

}  // namespace mostar::identity
