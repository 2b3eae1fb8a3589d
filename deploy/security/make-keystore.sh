#!/usr/bin/env bash
# Makes (or adds to) a DDS Security keystore for an ispars fleet, with openssl only.
#
#   deploy/security/make-keystore.sh [--days N] KEYSTORE ROLE:NAME [ROLE:NAME...]
#
# ROLE is one of
#   daemon    an isparsd: reads requests; writes replies, roadmap updates, statuses, announcements
#   operator  a client that may change what daemons hold (load, unload, build, extend, cancel, drop)
#   viewer    a client that may query and follow updates and statuses, and change nothing
# NAME is the identity's common name (letters, digits, '.', '_', '-'; at most 64).
#
# KEYSTORE gets, on first use, one certificate authority (ca/ca.pem and its key ca/ca.key, which
# signs both the identities and the access-control documents) and governance.p7s: every ispars
# topic authenticated, access-controlled and encrypted, with origin authentication, and no
# unauthenticated participant admitted. Each identity gets identities/NAME/ with cert.pem, key.pem,
# permissions.p7s (what its role may publish and subscribe), and copies of ca.pem and
# governance.p7s: that directory is all one process needs. Give a process its identity with
# `isparsd --security KEYSTORE/identities/NAME` or `ispars --security ...` (or ISPARS_SECURITY).
# Keep ca/ca.key off the fleet machines: copy only the identity's own directory. Running the script again with new names reuses the authority.
set -euo pipefail

days=3650
if [[ "${1:-}" == "--days" ]]; then
  days="$2"
  shift 2
fi
if [[ $# -lt 2 || ! "$days" =~ ^[0-9]+$ || "$days" -lt 1 || "$days" -gt 36500 ]]; then
  sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//' >&2
  echo "make-keystore.sh: need --days in 1..36500, a KEYSTORE and at least one ROLE:NAME" >&2
  exit 2
fi
store="$1"
shift
command -v openssl >/dev/null || { echo "make-keystore.sh: openssl is needed" >&2; exit 1; }

for spec in "$@"; do
  role="${spec%%:*}"
  name="${spec#*:}"
  case "$role" in daemon | operator | viewer) ;; *)
    echo "make-keystore.sh: unknown role '$role' in '$spec' (daemon, operator or viewer)" >&2
    exit 2
    ;;
  esac
  if [[ ! "$name" =~ ^[A-Za-z0-9._-]{1,64}$ || "$name" == "$spec" ]]; then
    echo "make-keystore.sh: bad identity name in '$spec' (letters, digits, '.', '_', '-'; 1..64)" >&2
    exit 2
  fi
done

umask 077
mkdir -p "$store/ca" "$store/identities"
ca="$store/ca/ca.pem"
ca_key="$store/ca/ca.key"
not_before="$(date -u -d '-1 day' +%Y-%m-%dT%H:%M:%S)"  # a day of clock skew between machines
not_after="$(date -u -d "+$days days" +%Y-%m-%dT%H:%M:%S)"
domains='<domains><id_range><min>0</min><max>232</max></id_range></domains>'

sign() {  # sign XML into S/MIME, as the access-control plugin reads it
  openssl smime -sign -text -in "$1" -out "$2" -signer "$ca" -inkey "$ca_key" 2>/dev/null
}

if [[ ! -f "$ca" ]]; then
  openssl ecparam -name prime256v1 -genkey -noout -out "$ca_key"
  openssl req -x509 -new -key "$ca_key" -out "$ca" -days "$days" -sha256 -subj "/O=ispars/CN=ispars fleet CA" 2>/dev/null
  cat >"$store/governance.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<!-- ispars fleet governance: no unauthenticated participant joins; every ispars topic is
     discovered, read and written only by subjects whose permissions allow it, and its data and
     metadata are encrypted with origin authentication (a peer cannot pose as another). -->
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
  <domain_access_rules>
    <domain_rule>
      $domains
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>ENCRYPT_WITH_ORIGIN_AUTHENTICATION</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT_WITH_ORIGIN_AUTHENTICATION</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
XML
  sign "$store/governance.xml" "$store/governance.p7s"
fi

# The first 6 bytes of the GUID prefix of any participant holding `cert`, as PKI-DH fixes them:
# a 1 bit, then the first 47 bits of SHA-256 over the DER of the certificate's subject name.
prefix_head() {
  local der sub offset header length md
  der="$(mktemp)"
  openssl x509 -in "$1" -outform DER -out "$der"
  # tbsCertificate's SEQUENCEs at depth 2: signature algorithm, issuer, validity, subject.
  sub="$(openssl asn1parse -inform DER -in "$der" | awk '/d=2/ && /SEQUENCE/ { n++; if (n == 4) { print; exit } }')"
  offset="$(sed -E 's/^ *([0-9]+):.*/\1/' <<<"$sub")"
  header="$(sed -E 's/.*hl= *([0-9]+).*/\1/' <<<"$sub")"
  length="$(sed -E 's/.* l= *([0-9]+).*/\1/' <<<"$sub")"
  md="$(tail -c +"$((offset + 1))" "$der" | head -c "$((header + length))" | openssl dgst -sha256 -r | cut -c1-12)"
  rm -f "$der"
  local -a b
  for i in 0 1 2 3 4 5; do b[i]=$((16#${md:2*i:2})); done
  printf '%02x' $((0x80 | (b[0] >> 1)))
  for i in 1 2 3 4 5; do printf '%02x' $((((b[i - 1] << 7) | (b[i] >> 1)) & 0xff)); done
}

topics() { local t; printf '<topics>'; for t in "$@"; do printf '<topic>%s</topic>' "$t"; done; printf '</topics>'; }

for spec in "$@"; do
  role="${spec%%:*}"
  name="${spec#*:}"
  dir="$store/identities/$name"
  if [[ -e "$dir" ]]; then
    echo "make-keystore.sh: $dir exists; remove it to issue '$name' again" >&2
    exit 1
  fi
  mkdir -p "$dir"
  openssl ecparam -name prime256v1 -genkey -noout -out "$dir/key.pem"
  openssl req -new -key "$dir/key.pem" -out "$dir/cert.csr" -subj "/O=ispars/CN=$name" 2>/dev/null
  openssl x509 -req -in "$dir/cert.csr" -CA "$ca" -CAkey "$ca_key" -CAcreateserial -out "$dir/cert.pem" \
    -days "$days" -sha256 2>/dev/null
  rm -f "$dir/cert.csr"
  subject="$(openssl x509 -in "$dir/cert.pem" -noout -subject -nameopt RFC2253 | sed 's/^subject=//')"
  own="ispars.client.$(prefix_head "$dir/cert.pem")*"
  own_partition="<partitions><partition>$own</partition></partitions>"
  case "$role" in
    daemon)
      rules="<publish>$(topics ispars/status ispars/updates ispars/daemons ispars/tasks)</publish>
        <publish>$(topics ispars/reply ispars/tour_progress)<partitions><partition>ispars.client.*</partition></partitions></publish>
        <subscribe>$(topics ispars/query ispars/change ispars/status ispars/daemons ispars/tasks)</subscribe>"
      ;;
    operator | viewer)
      writes="ispars/query"
      [[ "$role" == operator ]] && writes="ispars/query ispars/change"
      # shellcheck disable=SC2086
      rules="<publish>$(topics $writes)</publish>
        <subscribe>$(topics ispars/status ispars/daemons ispars/updates)</subscribe>
        <subscribe>$(topics ispars/reply ispars/tour_progress)$own_partition</subscribe>"
      ;;
  esac
  cat >"$dir/permissions.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<!-- ispars $role '$name'. Replies and tour progress: only this subject's own partitions. -->
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
  <permissions>
    <grant name="$name">
      <subject_name>$subject</subject_name>
      <validity><not_before>$not_before</not_before><not_after>$not_after</not_after></validity>
      <allow_rule>
        $domains
        $rules
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
XML
  sign "$dir/permissions.xml" "$dir/permissions.p7s"
  cp "$ca" "$dir/ca.pem"  # the directory is all a process needs: copy it alone to a machine
  cp "$store/governance.p7s" "$dir/governance.p7s"
  echo "$role" >"$dir/role"
  echo "$own" >"$dir/reply_partitions"
  echo "$role $name: $dir"
done
