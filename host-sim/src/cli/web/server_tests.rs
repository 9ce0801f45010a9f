//! The connection bound and the reply deadline, in process with small
//! limits: the test accepts, and hands each connection to `start` as the
//! accept loop would (no loop is left running).

use super::super::site::Page;
use super::*;
use crate::cli::carried::Firmware;
use std::net::TcpListener;

const SMALL: Limits = Limits { connections: 1, head: Duration::from_secs(2), reply: Duration::from_millis(300) };

/// A folder holding one file far bigger than loopback's socket buffers.
fn page_with_big_file() -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("polyturn-web-deadline-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("big.wasm"), vec![0u8; 32 << 20]).unwrap();
    std::fs::canonicalize(d).unwrap()
}

#[test]
fn a_client_that_never_reads_its_reply_gives_its_place_back_at_the_reply_deadline() {
    let root = page_with_big_file();
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap();
    let open = Arc::new(AtomicUsize::new(0));
    let site = Arc::new(Site::new(Page::Folder(root.clone()), None));
    let mut stalled = TcpStream::connect(addr).unwrap();
    stalled.write_all(b"GET /big.wasm HTTP/1.1\r\n\r\n").unwrap();
    let started = Instant::now();
    assert!(start(listener.accept().unwrap().0, &site, SMALL, &open).is_ok());
    // the one place is taken: the next connection is given back for a 503
    let _second = TcpStream::connect(addr).unwrap();
    assert!(start(listener.accept().unwrap().0, &site, SMALL, &open).is_err());
    while open.load(Ordering::Acquire) != 0 {
        assert!(started.elapsed() < Duration::from_secs(5), "a stalled reader kept its place past the deadline");
        std::thread::sleep(Duration::from_millis(20));
    }
    let took = started.elapsed();
    let _ = std::fs::remove_dir_all(&root);
    assert!(took >= Duration::from_millis(250), "the reply was given up after {took:?}, before its deadline");
}

/// One GET over a real socket, answered by `start`; the whole reply.
fn get(site: &Arc<Site>, target: &str) -> String {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let mut client = TcpStream::connect(listener.local_addr().unwrap()).unwrap();
    client.write_all(format!("GET {target} HTTP/1.1\r\n\r\n").as_bytes()).unwrap();
    let open = Arc::new(AtomicUsize::new(0));
    assert!(start(listener.accept().unwrap().0, site, SMALL, &open).is_ok());
    let mut reply = String::new();
    client.read_to_string(&mut reply).unwrap();
    reply
}

#[test]
fn a_carried_page_and_firmware_are_served_with_their_length_and_type() {
    let fw = Firmware { name: "polyturn-9.9.9-stm32f411ce.bin", bytes: b"the image" };
    let site = Arc::new(Site::new(Page::Carried(&[("pkg/a.wasm", b"\0asm-bytes")]), Some(fw)));
    let wasm = get(&site, "/pkg/a.wasm");
    assert!(wasm.starts_with("HTTP/1.1 200 OK\r\nContent-Type: application/wasm\r\nContent-Length: 10\r\n"), "{wasm}");
    assert!(wasm.ends_with("\r\n\r\n\0asm-bytes"), "{wasm}");
    // every page file says where the image is, for the Flash view
    assert!(wasm.contains("\r\nX-Polyturn-Firmware: firmware/polyturn-9.9.9-stm32f411ce.bin\r\n"), "{wasm}");
    let image = get(&site, "/firmware/polyturn-9.9.9-stm32f411ce.bin");
    assert!(image.starts_with("HTTP/1.1 200 OK\r\n") && image.ends_with("\r\n\r\nthe image"), "{image}");
    assert!(get(&site, "/index.html").starts_with("HTTP/1.1 404 Not Found\r\n"));
    let without = Arc::new(Site::new(Page::Carried(&[("pkg/a.wasm", b"\0asm-bytes")]), None));
    assert!(!get(&without, "/pkg/a.wasm").contains("X-Polyturn-Firmware"));
}
