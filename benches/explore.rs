//! The explorer's pictures against the CLI process making the same picture
//! (issue 28: the design parsed, solved and prepared once per server, so a
//! picture from the API comes back faster than `bcifs render`). Both run
//! here, interleaved by criterion, on the release binary: the ratio of the
//! two times is the figure, not either time alone.

use std::io::{BufRead as _, BufReader, Read as _, Write as _};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};

const BIN: &str = env!("CARGO_BIN_EXE_bcifs");

/// `bcifs explore DESIGN` on a free port, stopped when dropped.
struct Server {
    child: Child,
    port: u16,
}

impl Server {
    fn start(design: &str) -> Server {
        let mut child = Command::new(BIN)
            .args(["explore", design, "--port", "0", "--no-open"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("bcifs explore starts");
        let mut line = String::new();
        BufReader::new(child.stdout.as_mut().expect("stdout")).read_line(&mut line).expect("the URL");
        let port = line.trim().trim_start_matches("http://127.0.0.1:").trim_end_matches('/').parse().expect("a port");
        Server { child, port }
    }

    /// The body of `GET path`, checked to be a PNG.
    fn picture(&self, path: &str) -> usize {
        let mut stream = TcpStream::connect(("127.0.0.1", self.port)).expect("connects");
        write!(stream, "GET {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n").expect("sends");
        let mut raw = Vec::new();
        stream.read_to_end(&mut raw).expect("reads");
        assert!(raw.starts_with(b"HTTP/1.1 200"), "{}", String::from_utf8_lossy(&raw[..raw.len().min(300)]));
        raw.len()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn pictures(c: &mut Criterion) {
    let out = std::env::temp_dir().join(format!("bcifs-bench-explore-{}.png", std::process::id()));
    let mut g = c.benchmark_group("explore_picture_640");
    g.sample_size(20);
    for (design, depth) in [("doo_sabin_torus", 4), ("doo_sabin_torus", 6), ("koch", 7), ("fern", 8)] {
        let server = Server::start(design);
        let case = format!("{design}_depth{depth}");
        g.bench_function(BenchmarkId::new("api", &case), |b| {
            b.iter(|| server.picture(&format!("/api/picture.png?depth={depth}&size=640x640")))
        });
        g.bench_function(BenchmarkId::new("cli_process", &case), |b| {
            b.iter(|| {
                let status = Command::new(BIN)
                    .args(["render", design, "--depth", &depth.to_string(), "--size", "640x640", "-o"])
                    .arg(&out)
                    .stdout(Stdio::null())
                    .stderr(Stdio::null())
                    .status()
                    .expect("bcifs render runs");
                assert!(status.success());
            })
        });
    }
    g.finish();
    let _ = std::fs::remove_file(&out);
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = pictures
}
criterion_main!(benches);
