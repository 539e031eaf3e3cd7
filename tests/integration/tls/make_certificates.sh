#!/usr/bin/env bash
# The certificates of the Modbus/TCP Security tests (SPEC §11), made with the openssl
# command line only, as docs/security.md tells an integrator to: a CA, the server's
# certificate for 127.0.0.1, clients with the role extension 1.3.6.1.4.1.50316.802.1, a
# client without a role, a client whose role holds a newline (a forger of log and monitor
# lines), and a client signed by another CA. ECDSA P-256 throughout.
#   make_certificates.sh DIR
set -euo pipefail
dir=$1
mkdir -p "$dir"
cd "$dir"
cat > extensions.cnf <<'CNF'
[server]
basicConstraints = critical, CA:FALSE
keyUsage = critical, digitalSignature
extendedKeyUsage = serverAuth
subjectAltName = IP:127.0.0.1, DNS:localhost
[client]
basicConstraints = critical, CA:FALSE
keyUsage = critical, digitalSignature
extendedKeyUsage = clientAuth
[operator]
basicConstraints = critical, CA:FALSE
keyUsage = critical, digitalSignature
extendedKeyUsage = clientAuth
1.3.6.1.4.1.50316.802.1 = ASN1:UTF8String:operator
[viewer]
basicConstraints = critical, CA:FALSE
keyUsage = critical, digitalSignature
extendedKeyUsage = clientAuth
1.3.6.1.4.1.50316.802.1 = ASN1:UTF8String:viewer
[forger]
basicConstraints = critical, CA:FALSE
keyUsage = critical, digitalSignature
extendedKeyUsage = clientAuth
# The DER of the UTF8String "viewer\nFORGED line from a certificate": the config syntax
# cannot write a newline, the DER can.
1.3.6.1.4.1.50316.802.1 = DER:0C:25:76:69:65:77:65:72:0A:46:4F:52:47:45:44:20:6C:69:6E:65:20:66:72:6F:6D:20:61:20:63:65:72:74:69:66:69:63:61:74:65
CNF
key() { openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:P-256 -out "$1.key" 2>/dev/null; }
ca() {  # name
  key "$1"
  openssl req -x509 -new -key "$1.key" -subj "/O=Plant/CN=$1" -days 30 -out "$1.pem" \
    -addext "basicConstraints=critical,CA:TRUE" -addext "keyUsage=critical,keyCertSign,cRLSign" 2>/dev/null
}
signed() {  # name, ca, extensions section, [days]
  key "$1"
  openssl req -new -key "$1.key" -subj "/O=Plant/CN=$1" -out "$1.csr" 2>/dev/null
  openssl x509 -req -in "$1.csr" -CA "$2.pem" -CAkey "$2.key" -CAcreateserial -days "${4:-30}" \
    -extfile extensions.cnf -extensions "$3" -out "$1.pem" 2>/dev/null
  rm "$1.csr"
}
ca ca
ca other-ca
signed server ca server
signed server-renewed ca server
signed operator ca operator
signed viewer ca viewer
signed norole ca client
signed forger ca forger
signed stranger other-ca operator
