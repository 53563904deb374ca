/*
 * The C side of the EtherNet/IP TLS server: owns mbedTLS's contexts (the configuration, the
 * DRBG, the device certificate and key, the trusted CA and one SSL context per session slot)
 * as statics, installs the static arena as mbedTLS's only heap, and gives the Rust side a few
 * calls that take the slot and the I/O context of the call (src/ffi.rs declares them).
 * Record bytes go through enip_tls_bio_send / enip_tls_bio_recv (Rust, non-blocking) and
 * entropy comes from enip_tls_entropy (Rust, the board's RNG).
 */
#include <stddef.h>
#include <string.h>

#include "mbedtls/ctr_drbg.h"
#include "mbedtls/memory_buffer_alloc.h"
#include "mbedtls/pk.h"
#include "mbedtls/platform.h"
#include "mbedtls/ssl.h"
#include "mbedtls/x509_crt.h"

#ifndef ENIP_TLS_SLOTS
#define ENIP_TLS_SLOTS 3
#endif
#ifndef ENIP_TLS_ARENA_BYTES
#define ENIP_TLS_ARENA_BYTES (40 * 1024)
#endif

int enip_tls_entropy(void *ctx, unsigned char *out, size_t len);
int enip_tls_bio_send(void *io, const unsigned char *buf, size_t len);
int enip_tls_bio_recv(void *io, unsigned char *buf, size_t len);

static unsigned char arena[ENIP_TLS_ARENA_BYTES] __attribute__((aligned(8)));
static mbedtls_ctr_drbg_context drbg;
static mbedtls_ssl_config conf;
static mbedtls_x509_crt own_cert;
static mbedtls_x509_crt trusted;
static mbedtls_pk_context own_key;
static mbedtls_ssl_context slots[ENIP_TLS_SLOTS];
static int ready;

/* The suites built in, in the order EtherNet/IP Security lists them. */
static const int available[] = {
    MBEDTLS_TLS_ECDHE_ECDSA_WITH_AES_128_CBC_SHA256,
    MBEDTLS_TLS_ECDHE_ECDSA_WITH_AES_256_CBC_SHA384,
    MBEDTLS_TLS_ECDHE_ECDSA_WITH_AES_128_GCM_SHA256,
    MBEDTLS_TLS_ECDHE_ECDSA_WITH_AES_256_GCM_SHA384,
};
#define AVAILABLE (sizeof(available) / sizeof(available[0]))
/* The suites offered to the next handshakes (zero-terminated): the CBC pair until told. */
static int offered[AVAILABLE + 1] = {
    MBEDTLS_TLS_ECDHE_ECDSA_WITH_AES_128_CBC_SHA256,
    MBEDTLS_TLS_ECDHE_ECDSA_WITH_AES_256_CBC_SHA384,
    0,
};

void *enip_tls_no_calloc(size_t n, size_t size)
{
    (void)n;
    (void)size;
    return NULL;
}

void enip_tls_no_free(void *ptr)
{
    (void)ptr;
}

size_t enip_tls_arena_bytes(void)
{
    return sizeof(arena);
}

size_t enip_tls_slots(void)
{
    return ENIP_TLS_SLOTS;
}

int enip_tls_setup(const unsigned char *cert, size_t cert_len, const unsigned char *key,
                   size_t key_len, const unsigned char *ca, size_t ca_len)
{
    static const unsigned char personal[] = "enip-tls";
    int ret;
    size_t i;

    if (ready) {
        return -1;
    }
    mbedtls_memory_buffer_alloc_init(arena, sizeof(arena));
    mbedtls_ctr_drbg_init(&drbg);
    mbedtls_x509_crt_init(&own_cert);
    mbedtls_x509_crt_init(&trusted);
    mbedtls_pk_init(&own_key);
    mbedtls_ssl_config_init(&conf);
    for (i = 0; i < ENIP_TLS_SLOTS; i++) {
        mbedtls_ssl_init(&slots[i]);
    }
    ret = mbedtls_ctr_drbg_seed(&drbg, enip_tls_entropy, NULL, personal, sizeof(personal) - 1);
    if (ret != 0) {
        return ret;
    }
    ret = mbedtls_x509_crt_parse_der(&own_cert, cert, cert_len);
    if (ret != 0) {
        return ret;
    }
    ret = mbedtls_pk_parse_key(&own_key, key, key_len, NULL, 0);
    if (ret != 0) {
        return ret;
    }
    ret = mbedtls_ssl_config_defaults(&conf, MBEDTLS_SSL_IS_SERVER, MBEDTLS_SSL_TRANSPORT_STREAM,
                                      MBEDTLS_SSL_PRESET_DEFAULT);
    if (ret != 0) {
        return ret;
    }
    mbedtls_ssl_conf_rng(&conf, mbedtls_ctr_drbg_random, &drbg);
    mbedtls_ssl_conf_min_version(&conf, MBEDTLS_SSL_MAJOR_VERSION_3, MBEDTLS_SSL_MINOR_VERSION_3);
    mbedtls_ssl_conf_max_version(&conf, MBEDTLS_SSL_MAJOR_VERSION_3, MBEDTLS_SSL_MINOR_VERSION_3);
    mbedtls_ssl_conf_ciphersuites(&conf, offered);
    ret = mbedtls_ssl_conf_own_cert(&conf, &own_cert, &own_key);
    if (ret != 0) {
        return ret;
    }
    if (ca_len > 0) {
        ret = mbedtls_x509_crt_parse_der(&trusted, ca, ca_len);
        if (ret != 0) {
            return ret;
        }
        mbedtls_ssl_conf_ca_chain(&conf, &trusted, NULL);
        mbedtls_ssl_conf_authmode(&conf, MBEDTLS_SSL_VERIFY_REQUIRED);
    } else {
        mbedtls_ssl_conf_authmode(&conf, MBEDTLS_SSL_VERIFY_NONE);
    }
    ready = 1;
    return 0;
}

/* Offers, from the next handshake on, those of the IANA suite numbers `ids` that are built in,
 * in their order (none: every handshake fails); returns how many. The list is the
 * configuration's, so sessions running their handshake meanwhile may see the change. */
int enip_tls_offer(const unsigned short *ids, size_t n)
{
    size_t i, j, k = 0, m;
    int seen;

    for (i = 0; i < n && k < AVAILABLE; i++) {
        for (j = 0; j < AVAILABLE; j++) {
            if (available[j] != (int)ids[i]) {
                continue;
            }
            seen = 0;
            for (m = 0; m < k; m++) {
                seen |= offered[m] == available[j];
            }
            if (!seen) {
                offered[k++] = available[j];
            }
        }
    }
    offered[k] = 0;
    return (int)k;
}

static mbedtls_ssl_context *slot(size_t index, void *io)
{
    if (!ready || index >= ENIP_TLS_SLOTS) {
        return NULL;
    }
    mbedtls_ssl_set_bio(&slots[index], io, enip_tls_bio_send, enip_tls_bio_recv, NULL);
    return &slots[index];
}

int enip_tls_open(size_t index)
{
    if (!ready || index >= ENIP_TLS_SLOTS) {
        return -1;
    }
    mbedtls_ssl_free(&slots[index]);
    mbedtls_ssl_init(&slots[index]);
    return mbedtls_ssl_setup(&slots[index], &conf);
}

int enip_tls_handshake(size_t index, void *io)
{
    mbedtls_ssl_context *ssl = slot(index, io);
    return ssl == NULL ? -1 : mbedtls_ssl_handshake(ssl);
}

int enip_tls_read(size_t index, void *io, unsigned char *buf, size_t len)
{
    mbedtls_ssl_context *ssl = slot(index, io);
    return ssl == NULL ? -1 : mbedtls_ssl_read(ssl, buf, len);
}

int enip_tls_write(size_t index, void *io, const unsigned char *buf, size_t len)
{
    mbedtls_ssl_context *ssl = slot(index, io);
    return ssl == NULL ? -1 : mbedtls_ssl_write(ssl, buf, len);
}

int enip_tls_close_notify(size_t index, void *io)
{
    mbedtls_ssl_context *ssl = slot(index, io);
    return ssl == NULL ? -1 : mbedtls_ssl_close_notify(ssl);
}

void enip_tls_close(size_t index)
{
    if (index < ENIP_TLS_SLOTS) {
        mbedtls_ssl_free(&slots[index]);
        mbedtls_ssl_init(&slots[index]);
    }
}
