#!/usr/bin/env bash
# Makes a self-signed CA, a server certificate and a client certificate for trying TLS and
# mutual TLS with vscand. Not for production: the CA key sits next to the certificates.
#
#   scripts/make-test-certs.sh DIR [NAME...]
#
# DIR receives ca.crt, ca.key, server.crt, server.key, client.crt and client.key. The server
# certificate is valid for localhost and 127.0.0.1 plus each NAME (a host name or an IP address).
# VSCAN_CERT_DAYS sets the validity (default 30 days).
set -euo pipefail

if [[ $# -lt 1 || "$1" == -* ]]; then
  echo "usage: $0 DIR [NAME...]" >&2
  exit 2
fi
DIR="$1"
shift
DAYS="${VSCAN_CERT_DAYS:-30}"

san="DNS:localhost,IP:127.0.0.1"
for name in "$@"; do
  if [[ "$name" =~ ^[0-9.]+$ || "$name" == *:* ]]; then
    san+=",IP:$name"
  else
    san+=",DNS:$name"
  fi
done

mkdir -p "$DIR"
cd "$DIR"
umask 077
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

new_key() { openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:P-256 -out "$1" 2>/dev/null; }

# The CA: self-signed, allowed to sign certificates and nothing else.
new_key ca.key
openssl req -x509 -new -key ca.key -sha256 -days "$DAYS" -subj "/CN=vscan test CA" \
  -addext "basicConstraints=critical,CA:TRUE" -addext "keyUsage=critical,keyCertSign,cRLSign" \
  -out ca.crt

# sign NAME SUBJECT EXTENSIONS: NAME.key and NAME.crt signed by the CA.
sign() {
  new_key "$1.key"
  openssl req -new -key "$1.key" -subj "$2" -out "$work/$1.csr"
  printf '%s\n' "basicConstraints=critical,CA:FALSE" "keyUsage=critical,digitalSignature" "$3" >"$work/$1.ext"
  openssl x509 -req -in "$work/$1.csr" -CA ca.crt -CAkey ca.key -CAcreateserial -CAserial "$work/ca.srl" \
    -sha256 -days "$DAYS" -extfile "$work/$1.ext" -out "$1.crt" 2>/dev/null
}

sign server "/CN=vscand" "extendedKeyUsage=serverAuth
subjectAltName=$san"
sign client "/CN=vscan client" "extendedKeyUsage=clientAuth"

chmod 0644 ca.crt server.crt client.crt
echo "wrote ca.crt ca.key server.crt server.key client.crt client.key to $(pwd) (server names: $san)"
