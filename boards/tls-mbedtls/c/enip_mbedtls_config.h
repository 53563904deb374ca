/*
 * mbedTLS 2.28 configuration of the EtherNet/IP TLS path on the microcontroller boards:
 * a TLS 1.2 server with the Confidentiality profile's ECDHE-ECDSA suites (AES-128/256 in CBC
 * with SHA-256/384 and in GCM), P-256 only, X.509 certificates in DER (device certificate and
 * CA verification), no filesystem, no sockets, no clock, no libc heap: every allocation comes
 * from the static arena the shim hands to MBEDTLS_MEMORY_BUFFER_ALLOC_C.
 */
#ifndef ENIP_MBEDTLS_CONFIG_H
#define ENIP_MBEDTLS_CONFIG_H

#include <stddef.h>

/* System: no MBEDTLS_HAVE_TIME, so certificate validity dates are not checked. */
#define MBEDTLS_HAVE_ASM
#define MBEDTLS_NO_PLATFORM_ENTROPY
#define MBEDTLS_PLATFORM_C
#define MBEDTLS_PLATFORM_MEMORY
#define MBEDTLS_MEMORY_BUFFER_ALLOC_C
/* Until the arena is installed, allocation fails (no libc malloc is linked). */
void *enip_tls_no_calloc(size_t n, size_t size);
void enip_tls_no_free(void *ptr);
#define MBEDTLS_PLATFORM_STD_CALLOC enip_tls_no_calloc
#define MBEDTLS_PLATFORM_STD_FREE enip_tls_no_free
/* The arena's corruption checks stop here (a trap: the board's fault handler) instead of exit. */
#define MBEDTLS_PLATFORM_EXIT_MACRO(status) __builtin_trap()

/* Symmetric crypto and hashes: AES (tables in flash), CBC and GCM, SHA-256 and SHA-384. */
#define MBEDTLS_AES_C
#define MBEDTLS_AES_ROM_TABLES
#define MBEDTLS_AES_FEWER_TABLES
#define MBEDTLS_CIPHER_C
#define MBEDTLS_CIPHER_MODE_CBC
#define MBEDTLS_GCM_C
#define MBEDTLS_MD_C
#define MBEDTLS_SHA256_C
#define MBEDTLS_SHA512_C
#define MBEDTLS_CTR_DRBG_C

/* Public key: ECDHE and ECDSA on P-256. */
#define MBEDTLS_BIGNUM_C
#define MBEDTLS_ECP_C
#define MBEDTLS_ECP_DP_SECP256R1_ENABLED
#define MBEDTLS_ECP_NIST_OPTIM
#define MBEDTLS_ECP_WINDOW_SIZE 2
#define MBEDTLS_ECP_FIXED_POINT_OPTIM 0
#define MBEDTLS_ECDH_C
#define MBEDTLS_ECDSA_C
#define MBEDTLS_ASN1_PARSE_C
#define MBEDTLS_ASN1_WRITE_C
#define MBEDTLS_OID_C
#define MBEDTLS_PK_C
#define MBEDTLS_PK_PARSE_C

/* X.509: the device certificate and the trusted CA, DER. */
#define MBEDTLS_X509_USE_C
#define MBEDTLS_X509_CRT_PARSE_C
#define MBEDTLS_X509_MAX_INTERMEDIATE_CA 2

/* TLS 1.2 server. */
#define MBEDTLS_SSL_TLS_C
#define MBEDTLS_SSL_SRV_C
#define MBEDTLS_SSL_PROTO_TLS1_2
#define MBEDTLS_KEY_EXCHANGE_ECDHE_ECDSA_ENABLED
#define MBEDTLS_SSL_ENCRYPT_THEN_MAC
#define MBEDTLS_SSL_EXTENDED_MASTER_SECRET
#define MBEDTLS_SSL_MAX_FRAGMENT_LENGTH
#define MBEDTLS_SSL_CIPHERSUITES                        \
    MBEDTLS_TLS_ECDHE_ECDSA_WITH_AES_128_CBC_SHA256,    \
    MBEDTLS_TLS_ECDHE_ECDSA_WITH_AES_256_CBC_SHA384,    \
    MBEDTLS_TLS_ECDHE_ECDSA_WITH_AES_128_GCM_SHA256,    \
    MBEDTLS_TLS_ECDHE_ECDSA_WITH_AES_256_GCM_SHA384
/* Record buffers: 4 KiB each way per session. ENIP frames are under 600 bytes and a client's
 * certificate message well under 4 KiB; a peer sending a larger record (without having
 * negotiated max_fragment_length) has its connection closed. */
#define MBEDTLS_SSL_IN_CONTENT_LEN 4096
#define MBEDTLS_SSL_OUT_CONTENT_LEN 4096

#include "mbedtls/check_config.h"

#endif /* ENIP_MBEDTLS_CONFIG_H */
