//! The connection bound and the reply deadline, in process with small
//! limits: the test accepts, and hands each connection to `start` as the
//! accept loop would (no loop is left running).

use super::*;
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
    let mut stalled = TcpStream::connect(addr).unwrap();
    stalled.write_all(b"GET /big.wasm HTTP/1.1\r\n\r\n").unwrap();
    let started = Instant::now();
    assert!(start(listener.accept().unwrap().0, &root, SMALL, &open).is_ok());
    // the one place is taken: the next connection is given back for a 503
    let _second = TcpStream::connect(addr).unwrap();
    assert!(start(listener.accept().unwrap().0, &root, SMALL, &open).is_err());
    while open.load(Ordering::Acquire) != 0 {
        assert!(started.elapsed() < Duration::from_secs(5), "a stalled reader kept its place past the deadline");
        std::thread::sleep(Duration::from_millis(20));
    }
    let took = started.elapsed();
    let _ = std::fs::remove_dir_all(&root);
    assert!(took >= Duration::from_millis(250), "the reply was given up after {took:?}, before its deadline");
}
