//! Writes the seed corpus under `fuzz/corpus/seed/<target>/` and checks, by playing the TCP
//! and UDP scripts against the adapter, that every seed request gets a successful reply.
//!
//! Run from the repository root: `cargo run --manifest-path fuzz/Cargo.toml --example gen_seeds`.
//! It replaces the seeds it wrote before and keeps the inputs a fuzz campaign merged in.
//! With `--check` it writes nothing: it fails if a seed no longer gets a successful reply,
//! and warns if the committed seeds differ from what it would write.

use std::fs;
use std::path::{Path, PathBuf};

use enip_fuzz::frames::{self, Connection, IoScript, TcpScript, UdpScript};
use enip_fuzz::{io_script, profile, script};
use enip_profiles::Profile;
use enip_stack::wire::cpf;
use enip_stack::wire::encap::{command, Packet, HEADER_LEN};
use enip_stack::wire::forward_open::ForwardOpenReplyRepr;
use enip_stack::wire::message_router::ResponseRepr;
use enip_stack::wire::rr_data;

fn main() {
    let check_only = match std::env::args().nth(1).as_deref() {
        None => false,
        Some("--check") => true,
        Some(other) => {
            eprintln!("usage: gen_seeds [--check] (unexpected {other:?})");
            std::process::exit(2);
        }
    };
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("corpus/seed");
    let session = learn_session_handle();
    let requests = frames::requests();
    let mut seeds: Vec<(&str, String, Vec<u8>)> = Vec::new();
    let mut add = |target: &'static str, name: &str, bytes: Vec<u8>| {
        seeds.push((target, name.to_string(), bytes));
    };

    add(
        "encap_header",
        "register_session",
        frames::register_session(),
    );
    add("encap_header", "list_identity", frames::list_identity());
    for (name, req) in &requests[..3] {
        add("encap_header", name, frames::send_rr_data(session, req));
    }
    add("register_session", "v1", frames::REGISTER_DATA.to_vec());
    for (name, req) in &requests {
        add("cpf", name, frames::unconnected_cpf(req));
        add("message_router", name, req.clone());
        add("cip_request", name, req.clone());
    }
    let mut rr = vec![0, 0, 0, 0, 5, 0];
    rr.extend_from_slice(&frames::unconnected_cpf(&requests[0].1));
    add("cpf", "rr_data_prefix", rr);
    add(
        "epath",
        "class_instance_attribute",
        frames::path(0x01, 1, Some(7)),
    );
    add(
        "epath",
        "wide_logical",
        frames::path(0x04, 0x1234, Some(0x300)),
    );
    add("epath", "port1_link0", frames::ROUTE_PORT1_LINK0.to_vec());
    add(
        "epath",
        "port_ip_link",
        vec![
            0x12, 9, b'1', b'9', b'8', b'.', b'1', b'8', b'.', b'0', b'.', b'2', 0,
        ],
    );
    add(
        "epath",
        "symbolic",
        vec![0x91, 5, b'P', b'4', b'0', b'1', b'2', 0],
    );
    add(
        "epath",
        "connection_path",
        vec![
            0x34, 4, 0xFE, 0xFF, 0x0C, 0, 1, 0, 0x81, 1, // electronic key
            0x43, 10, // production inhibit
            0x20, 0x04, 0x24, 151, 0x2C, 150, 0x2C, 100, // assembly points
            0x80, 2, 1, 2, 3, 4, // data segment
        ],
    );
    add("identity_item", "list_identity_reply", identity_item_seed());
    add("lldp", "own_lldpdu", lldp_seed());
    // Request data after service and path (class 6, instance 1: 4 bytes).
    add(
        "forward_open",
        "forward_open",
        frames::forward_open()[6..].to_vec(),
    );
    add(
        "forward_open",
        "forward_close",
        frames::forward_close()[6..].to_vec(),
    );
    for target in ["message_router", "cip_request"] {
        add(target, "forward_open", frames::forward_open());
        add(target, "forward_close", frames::forward_close());
    }
    let o_t = learn_o_t_id(session, "test", &Connection::test_device());
    add("io_datagram", "o_t_run", frames::o_t_datagram(o_t, 1));
    for (target, name, bytes) in enip_fuzz::link_seeds::seeds(&frames::o_t_datagram(o_t, 1)) {
        add(target, name, bytes);
    }
    for (name, list) in enip_fuzz::device_lists::seeds() {
        add("device_list", name, list);
    }
    let mut io = IoScript::default()
        .accept(0)
        .tcp(0, &frames::register_session())
        .tcp(0, &frames::send_rr_data(session, &frames::forward_open()));
    for seq in 1..=4u16 {
        io = io.wait_ms(10).io(&frames::o_t_datagram(o_t, seq));
    }
    io = io
        .trigger()
        .wait_ms(10)
        .tcp(0, &frames::send_rr_data(session, &frames::forward_close()))
        .wait_ms(32)
        .close(0);
    add("adapter_io", "exclusive_owner", io.0);

    let mut full = TcpScript::default()
        .accept(0)
        .data(0, &frames::register_session());
    for (_, req) in &requests {
        full = full.data(0, &frames::send_rr_data(session, req));
    }
    add(
        "adapter_tcp",
        "session_all_requests",
        full.data(0, &frames::unregister_session(session)).0,
    );
    // Two frames in one segment, then one frame split across three segments.
    let identity = frames::send_rr_data(session, &requests[0].1);
    let mut two = frames::register_session();
    two.extend_from_slice(&identity);
    add(
        "adapter_tcp",
        "coalesced_and_split",
        TcpScript::default()
            .accept(0)
            .data(0, &two)
            .data(0, &identity[..10])
            .data(0, &identity[10..30])
            .data(0, &identity[30..])
            .close(0)
            .0,
    );
    add(
        "adapter_tcp",
        "three_sockets_list",
        TcpScript::default()
            .accept(0)
            .accept(1)
            .accept(2)
            .data(1, &frames::list_identity())
            .data(2, &frames::list_services())
            .data(0, &frames::register_session())
            .close(1)
            .0,
    );
    add(
        "adapter_udp",
        "unicast_and_broadcast",
        UdpScript::default()
            .unicast(&frames::list_identity())
            .unicast(&frames::list_services())
            .broadcast(&frames::list_identity())
            .broadcast(&frames::list_identity())
            .wait(4)
            .0,
    );

    // Every shipped profile as the adapter targets' device: a session with the identity
    // requests and the profile's manual requests, ListIdentity over UDP, and an exclusive
    // owner connection to its first configuration, output and input assemblies.
    for &name in Profile::NAMES {
        let manual = profile::seeds(name);
        let mut tcp = TcpScript::for_device(name)
            .accept(0)
            .data(0, &frames::register_session());
        for req in [&requests[0].1, &requests[1].1]
            .into_iter()
            .cloned()
            .chain(manual.iter().flat_map(|(_, s)| s.requests()))
        {
            tcp = tcp.data(0, &frames::send_rr_data(session, &req));
        }
        add_owned(&mut seeds, "adapter_tcp", format!("{name}_session"), tcp.0);
        let udp = UdpScript::for_device(name)
            .unicast(&frames::list_identity())
            .broadcast(&frames::list_identity())
            .wait(4);
        add_owned(
            &mut seeds,
            "adapter_udp",
            format!("{name}_list_identity"),
            udp.0,
        );
        let conn = Connection::of(&Profile::from_name(name).expect("profile"));
        let o_t = learn_o_t_id(session, name, &conn);
        let mut io = IoScript::for_device(name)
            .accept(0)
            .tcp(0, &frames::register_session())
            .tcp(0, &frames::send_rr_data(session, &conn.forward_open()));
        for seq in 1..=4u16 {
            io = io.wait_ms(10).io(&conn.o_t_datagram(o_t, seq, &[0]));
        }
        io = io
            .trigger()
            .wait_ms(10)
            .tcp(0, &frames::send_rr_data(session, &conn.forward_close()))
            .wait_ms(32)
            .close(0);
        add_owned(
            &mut seeds,
            "adapter_io",
            format!("{name}_exclusive_owner"),
            io.0,
        );
        // The profile target: its manual's examples.
        let target: &'static str = profile_target(name);
        for (seed, script) in manual {
            add_owned(&mut seeds, target, seed.to_string(), script.0);
        }
    }

    verify(&seeds, session);
    if check_only {
        let stale: Vec<String> = seeds
            .iter()
            .filter(|(target, name, bytes)| {
                fs::read(root.join(target).join(name)).ok().as_ref() != Some(bytes)
            })
            .map(|(target, name, _)| format!("{target}/{name}"))
            .collect();
        if stale.is_empty() {
            println!(
                "seeds: all {} up to date and answered successfully",
                seeds.len()
            );
        } else {
            println!(
                "warning: committed seeds differ from what gen_seeds writes: {}; refresh them \
                 with `cargo run --manifest-path fuzz/Cargo.toml --example gen_seeds`",
                stale.join(", ")
            );
        }
        return;
    }
    remove_written_seeds(&root);
    for (target, name, bytes) in &seeds {
        write(&root.join(target), name, bytes);
    }
    println!("wrote {} seeds under {}", seeds.len(), root.display());
}

fn add_owned(
    seeds: &mut Vec<(&str, String, Vec<u8>)>,
    target: &'static str,
    name: String,
    bytes: Vec<u8>,
) {
    seeds.push((target, name, bytes));
}

/// The per-profile target of the profile called `name` (`profile_<name with _>`); the
/// generic profile has no parsers of its own and no target.
fn profile_target(name: &str) -> &'static str {
    match name {
        "position-servo" => "profile_position_servo",
        "parker-ipa" => "profile_parker_ipa",
        "ametek-pls" => "profile_ametek_pls",
        "kollmorgen-akd" => "profile_kollmorgen_akd",
        _ => "",
    }
}

/// Removes every seed this program wrote before; the inputs `cargo xtask fuzz --campaign`
/// merged in (named by their SHA-1, 40 hex digits) stay.
fn remove_written_seeds(root: &Path) {
    let Ok(targets) = fs::read_dir(root) else {
        return;
    };
    for dir in targets.filter_map(|e| e.ok()).map(|e| e.path()) {
        for file in fs::read_dir(&dir)
            .into_iter()
            .flatten()
            .filter_map(|e| e.ok())
        {
            let name = file.file_name();
            let name = name.to_string_lossy();
            let merged = name.len() == 40 && name.bytes().all(|b| b.is_ascii_hexdigit());
            if !merged {
                fs::remove_file(file.path()).expect("remove old seed");
            }
        }
    }
}

fn write(dir: &Path, name: &str, bytes: &[u8]) {
    fs::create_dir_all(dir).expect("create seed dir");
    fs::write(dir.join(name), bytes).expect("write seed");
}

/// The session handle the fuzzed adapter hands to the first RegisterSession on socket 0.
fn learn_session_handle() -> u32 {
    let mut handle = None;
    let s = TcpScript::default()
        .accept(0)
        .data(0, &frames::register_session());
    script::run_tcp(&s.0, |_, reply| {
        handle = Packet::new_checked(reply).ok().map(|p| p.session_handle());
    });
    handle.expect("RegisterSession was answered")
}

/// The O->T connection ID the adapter around `device` picks for `conn`'s Forward_Open.
fn learn_o_t_id(session: u32, device: &str, conn: &Connection) -> u32 {
    let mut id = None;
    let s = IoScript::for_device(device)
        .accept(0)
        .tcp(0, &frames::register_session())
        .tcp(0, &frames::send_rr_data(session, &conn.forward_open()));
    io_script::run_io(&s.0, |_, reply| {
        let p = Packet::new_checked(reply).expect("frame");
        if p.command() != command::SEND_RR_DATA {
            return;
        }
        let rr = rr_data::Packet::new_checked(p.data()).expect("rr data");
        let c = cpf::Packet::new_checked(rr.cpf()).expect("cpf");
        let item = c.find(cpf::item_type::UNCONNECTED_DATA).expect("data item");
        let r = ResponseRepr::parse(item.data).expect("response");
        assert_eq!(r.general_status, 0, "Forward_Open failed: {r:02x?}");
        id = ForwardOpenReplyRepr::parse(r.data)
            .ok()
            .map(|f| f.o_t_connection_id);
    });
    id.expect("Forward_Open was answered")
}

/// The data of the identity item in the adapter's ListIdentity reply.
fn identity_item_seed() -> Vec<u8> {
    let mut item = None;
    let s = UdpScript::default().unicast(&frames::list_identity());
    script::run_udp(&s.0, |_, reply| {
        let p = Packet::new_checked(reply).expect("frame");
        let c = cpf::Packet::new_checked(p.data()).expect("cpf");
        item = c.items().next().map(|i| i.data.to_vec());
    });
    item.expect("ListIdentity was answered")
}

/// The test device's own LLDPDU (every TLV the adapter sends), as a neighbour's.
fn lldp_seed() -> Vec<u8> {
    let mut adapter = script::adapter(enip_fuzz::TestDevice::new());
    let mut out = [0u8; enip_stack::adapter::MAX_LLDPDU];
    let n = adapter.lldp_transmit(enip_stack::Instant::from_micros(0), &mut out);
    out[..n].to_vec()
}

/// Every reply to the TCP and UDP seed scripts must carry success, down to the CIP status.
fn verify(seeds: &[(&str, String, Vec<u8>)], session: u32) {
    for (target, name, bytes) in seeds {
        let mut replies = 0;
        match *target {
            "adapter_tcp" => script::run_tcp(bytes, |_, reply| {
                replies += 1;
                check_reply(name, reply, session);
            }),
            "adapter_udp" => script::run_udp(bytes, |_, reply| {
                replies += 1;
                check_reply(name, reply, session);
            }),
            "adapter_io" => {
                let stats = io_script::run_io(bytes, |_, reply| {
                    replies += 1;
                    check_reply(name, reply, session);
                });
                assert!(
                    stats.accepted > 0,
                    "{name}: no O->T data accepted: {stats:?}"
                );
                assert!(
                    stats.produced > 0,
                    "{name}: no T->O data produced: {stats:?}"
                );
                println!("{target}/{name}: {stats:?}");
            }
            t if t.starts_with("profile_") => {
                let device = Profile::NAMES
                    .iter()
                    .find(|&&n| profile_target(n) == t)
                    .expect("a profile target");
                for (req, status) in profile::run(device, bytes) {
                    assert_eq!(status, 0, "{t}/{name}: status of {req:02x?}");
                    replies += 1;
                }
            }
            _ => continue,
        }
        assert!(replies > 0, "{name}: no reply at all");
        println!("{target}/{name}: {replies} replies, all successful");
    }
}

fn check_reply(name: &str, reply: &[u8], session: u32) {
    let p = Packet::new_checked(reply).expect("frame");
    assert_eq!(
        p.status(),
        0,
        "{name}: encapsulation status in {reply:02x?}"
    );
    if p.command() == command::REGISTER_SESSION {
        assert_eq!(p.session_handle(), session, "{name}: handle");
    }
    if p.command() != command::SEND_RR_DATA {
        return;
    }
    let rr = rr_data::Packet::new_checked(p.data()).expect("rr data");
    let c = cpf::Packet::new_checked(rr.cpf()).expect("cpf");
    let data = c
        .find(cpf::item_type::UNCONNECTED_DATA)
        .expect("unconnected data item");
    let r = ResponseRepr::parse(data.data).expect("response");
    assert_eq!(
        r.general_status,
        0,
        "{name}: CIP status {:02x} ext {:?} in reply {:02x?}",
        r.general_status,
        r.extended_status(),
        &reply[HEADER_LEN..]
    );
}
