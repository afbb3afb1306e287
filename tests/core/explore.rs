//! `bcifs explore` over HTTP (std sockets, no client crate): the first line
//! of stdout is the URL; the JSON and image API answers what the page asks;
//! hostile requests get a 4xx with a JSON message; 50 concurrent requests
//! are all answered; a newer request for the same slot cancels the older;
//! Ctrl-C stops the server.

use std::io::{BufRead as _, BufReader, Read as _, Write as _};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};

/// A running explorer, stopped (SIGINT) when dropped; its stderr kept for failure messages.
struct Server {
    child: Child,
    port: u16,
    stderr: std::sync::Arc<std::sync::Mutex<String>>,
}

impl Server {
    fn start(design: &str) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_bcifs"))
            .args(["explore", design, "--port", "0", "--no-open"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("bcifs explore starts");
        let mut line = String::new();
        BufReader::new(child.stdout.as_mut().unwrap()).read_line(&mut line).unwrap();
        let url = line.trim();
        assert!(url.starts_with("http://127.0.0.1:") && url.ends_with('/'), "the URL first: {url:?}");
        let port = url.trim_start_matches("http://127.0.0.1:").trim_end_matches('/').parse().unwrap();
        let stderr = std::sync::Arc::new(std::sync::Mutex::new(String::new()));
        let (mut pipe, kept) = (child.stderr.take().unwrap(), stderr.clone());
        std::thread::spawn(move || {
            let mut text = String::new();
            let _ = pipe.read_to_string(&mut text);
            kept.lock().unwrap().push_str(&text);
        });
        Server { child, port, stderr }
    }

    /// `GET path` (the raw path, sent as is): status, headers, body.
    fn get(&self, path: &str) -> (u16, String, Vec<u8>) {
        let mut stream = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        write!(stream, "GET {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n").unwrap();
        let mut raw = Vec::new();
        stream.read_to_end(&mut raw).unwrap();
        let Some(split) = raw.windows(4).position(|w| w == b"\r\n\r\n") else {
            std::thread::sleep(std::time::Duration::from_millis(300));
            panic!(
                "GET {path}: no HTTP answer ({} bytes: {:?}); the server is {}; its stderr: {}",
                raw.len(),
                String::from_utf8_lossy(&raw[..raw.len().min(200)]),
                if TcpStream::connect(("127.0.0.1", self.port)).is_ok() { "listening" } else { "gone" },
                self.stderr.lock().unwrap()
            );
        };
        let head = String::from_utf8_lossy(&raw[..split]).to_string();
        let status = head.split_whitespace().nth(1).unwrap().parse().unwrap();
        let mut body = raw[split + 4..].to_vec();
        if head.to_lowercase().contains("transfer-encoding: chunked") {
            body = unchunk(&body);
        }
        (status, head, body)
    }

    fn json(&self, path: &str) -> (u16, serde_json::Value) {
        let (status, _, body) = self.get(path);
        (
            status,
            serde_json::from_slice(&body)
                .unwrap_or_else(|_| panic!("JSON from {path}: {:?}", String::from_utf8_lossy(&body))),
        )
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = Command::new("kill").args(["-INT", &self.child.id().to_string()]).status();
        let _ = self.child.wait();
    }
}

/// Sends `request` (raw HTTP) to the server on `port` and reads the whole answer.
fn exchange(port: u16, request: &str) -> String {
    let mut stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    stream.write_all(request.as_bytes()).unwrap();
    let mut raw = Vec::new();
    stream.read_to_end(&mut raw).unwrap();
    String::from_utf8_lossy(&raw).to_string()
}

fn unchunk(mut body: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let line_end = body.windows(2).position(|w| w == b"\r\n").unwrap_or(body.len());
        let size = usize::from_str_radix(String::from_utf8_lossy(&body[..line_end]).trim(), 16).unwrap_or(0);
        if size == 0 {
            return out;
        }
        out.extend_from_slice(&body[line_end + 2..line_end + 2 + size]);
        body = &body[line_end + 2 + size + 2..];
    }
}

#[test]
fn the_api_answers_the_page() {
    let server = Server::start("corner_cutting");
    let (status, design) = server.json("/api/design");
    assert_eq!(status, 200);
    assert_eq!(design["name"], "corner_cutting");
    assert_eq!(design["curve"], true);
    let a = &design["parameters"][0];
    assert_eq!((a["name"].as_str(), a["default"].as_f64()), (Some("a"), Some(0.25)));
    let (lo, hi) = (a["range"][0].as_f64().unwrap(), a["range"][1].as_f64().unwrap());
    assert!(lo < 0.25 && 0.25 < hi, "the convergence range holds the default: {lo}..{hi}");
    // The check is `bcifs check --json`'s object, with the curve's analysis beside it.
    let (status, check) = server.json("/api/check?a=0.25&b=0.25");
    assert_eq!(status, 200);
    assert_eq!(check["check"]["converges"], true);
    assert_eq!(check["curve"]["region"], "1", "Chaikin is tangent continuous");
    let (_, dimension) = server.json("/api/dimension?a=0.25&b=0.25");
    assert!((dimension["box_dimension"].as_f64().unwrap() - 1.0).abs() < 0.05);
    // The picture equals the one `bcifs render` draws with the same options.
    let (status, head, png) = server.get("/api/picture.png?a=0.3&depth=6&size=200x160");
    assert_eq!(status, 200, "{head}");
    assert!(head.contains("image/png"));
    let dir = std::env::temp_dir().join(format!("bcifs-explore-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cli = dir.join("cli.png");
    let out = Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["render", "corner_cutting", "--param", "a=0.3", "--depth", "6", "--size", "200x160", "-o"])
        .arg(&cli)
        .output()
        .unwrap();
    assert!(out.status.success());
    let (api, file) = (image::load_from_memory(&png).unwrap().to_rgb8(), image::open(&cli).unwrap().to_rgb8());
    assert_eq!(api.dimensions(), (200, 160));
    assert_eq!(api.as_raw(), file.as_raw(), "the same pixels as the CLI's PNG");
    // Maps: the verdict map's pixels are the sweep's colours; a cached second map is the same.
    let (status, _, map) = server.get("/api/map.png?x=a&y=b&kind=verdict&size=48");
    assert_eq!(status, 200);
    let map = image::load_from_memory(&map).unwrap().to_rgb8();
    assert_eq!(map.dimensions(), (48, 48));
    assert!(map.pixels().any(|p| p.0 == [150, 205, 150]), "converging pixels");
    // Exports: the current member, as a download.
    let (status, head, obj) = server.get("/api/export.obj?a=0.3&depth=4");
    assert_eq!(status, 200);
    assert!(head.contains("attachment; filename=\"corner_cutting.obj\""));
    let cli_obj = dir.join("cli.obj");
    let out = Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["render", "corner_cutting", "--param", "a=0.3", "--depth", "4", "-o"])
        .arg(&cli_obj)
        .output()
        .unwrap();
    assert!(out.status.success());
    assert_eq!(obj, std::fs::read(&cli_obj).unwrap(), "the same OBJ as `bcifs render`");
    let (status, _, toml) = server.get("/api/export.toml?a=0.3");
    assert_eq!(status, 200);
    let again = bcifs::parse_design(&String::from_utf8_lossy(&toml), "export.toml", "x").unwrap();
    assert_eq!(again.defaults()["a"], 0.3, "the parameters become the defaults");
    for ext in ["ply", "glb", "png"] {
        assert_eq!(server.get(&format!("/api/export.{ext}?depth=3")).0, 200, "{ext}");
    }
    // The page and its script.
    let (status, head, page) = server.get("/");
    assert_eq!(status, 200);
    assert!(head.contains("text/html") && String::from_utf8_lossy(&page).contains("explore.js"));
    assert_eq!(server.get("/explore.js").0, 200);
}

#[test]
fn hostile_requests_get_a_4xx_with_a_message() {
    let server = Server::start("corner_cutting");
    for (path, status, says) in [
        ("/api/picture.png?q=1", 400, "not a parameter"),
        ("/api/picture.png?a=abc", 400, "finite number"),
        ("/api/picture.png?a=inf", 400, "finite number"),
        ("/api/picture.png?depth=99", 400, "at most"),
        ("/api/picture.png?depth=-1", 400, "depth"),
        ("/api/picture.png?size=100000x100000", 400, "1 to 2048 pixels"),
        ("/api/picture.png?size=0x10", 400, "1 to 2048 pixels"),
        ("/api/picture.png?view=a,b", 400, "YAW,PITCH"),
        ("/api/picture.png?a=-0.9&b=0.95", 422, "diverges"),
        ("/api/map.png?x=a&y=a", 400, "different"),
        ("/api/map.png?x=a&y=b&size=100000", 400, "map size"),
        ("/api/map.png?x=a&y=b&kind=colour", 400, "unknown sweep"),
        ("/api/export.exe", 404, "no export"),
        ("/../../etc/passwd", 400, "`..`"),
        ("/%2e%2e/%2e%2e/etc/passwd", 400, "`..`"),
        ("/Cargo.toml", 404, "not found"),
        ("/api/nothing", 404, "not found"),
    ] {
        let (got, body) = server.json(path);
        assert_eq!(got, status, "{path}: {body}");
        assert!(body["error"].as_str().unwrap().contains(says), "{path}: {body}");
    }
    // A POST is refused; a request that is not HTTP does not stop the server.
    let mut stream = TcpStream::connect(("127.0.0.1", server.port)).unwrap();
    stream.write_all(b"\x00\x01garbage\r\n\r\n").unwrap();
    drop(stream);
    assert_eq!(server.json("/api/design").0, 200, "still serving");
}

#[test]
fn fifty_concurrent_requests_are_answered_and_a_newer_one_cancels_the_older() {
    let server = Server::start("doo_sabin_torus");
    let port = server.port;
    let threads: Vec<_> = (0..50)
        .map(|k| {
            std::thread::spawn(move || {
                let path = if k % 2 == 0 {
                    format!("/api/picture.png?alpha={}&depth=3&size=96x96", 0.55 + 0.001 * f64::from(k))
                } else {
                    "/api/check?beta=0.14".to_string()
                };
                let mut stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
                write!(stream, "GET {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n").unwrap();
                let mut raw = Vec::new();
                stream.read_to_end(&mut raw).unwrap();
                String::from_utf8_lossy(&raw[..12.min(raw.len())]).to_string()
            })
        })
        .collect();
    for t in threads {
        assert_eq!(t.join().unwrap(), "HTTP/1.1 200", "every request answered");
    }
    // A slow picture in the slot `picture`, then a newer one in the same slot: the older is cancelled (409).
    let slow = std::thread::spawn(move || {
        exchange(
            port,
            "GET /api/picture.png?depth=9&size=2000x2000&slot=picture HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n",
        )
    });
    std::thread::sleep(std::time::Duration::from_millis(700));
    assert_eq!(server.get("/api/picture.png?depth=2&size=64x64&slot=picture").0, 200);
    let older = slow.join().unwrap();
    assert!(older.starts_with("HTTP/1.1 409") && older.contains("cancelled"), "{}", &older[..older.len().min(300)]);
}

#[test]
fn ctrl_c_stops_the_server() {
    let mut server = Server::start("koch");
    assert_eq!(server.get("/api/design").0, 200);
    let _ = Command::new("kill").args(["-INT", &server.child.id().to_string()]).status();
    let started = std::time::Instant::now();
    let status = server.child.wait().unwrap();
    assert!(started.elapsed() < std::time::Duration::from_secs(3), "stopped within seconds");
    assert_eq!(status.code(), Some(130));
}

#[test]
fn a_one_parameter_family_has_a_strip_and_smooth_maps_follow_the_junction_angle() {
    // The ternary 5-point scheme with its tension free: ω alone, as a strip whose
    // columns are `bcifs check`'s verdicts at their centres.
    let dir = std::env::temp_dir().join(format!("bcifs-explore-strip-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("ternary5_w.toml");
    let out = Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["scheme", "ifs", "ternary5", "--omega", "w", "--print"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    std::fs::write(&file, &out.stdout).unwrap();
    let server = Server::start(file.to_str().unwrap());
    let (_, design) = server.json("/api/design");
    assert_eq!(design["parameters"].as_array().unwrap().len(), 1);
    assert_eq!(design["parameters"][0]["name"], "w");
    assert_eq!(design["parameters"][0]["default"].as_f64(), Some(0.06));
    let (status, head, png) = server.get("/api/map.png?x=w&xr=-0.2:0.3&kind=verdict&size=50");
    assert_eq!(status, 200, "{head}");
    let strip = image::load_from_memory(&png).unwrap().to_rgb8();
    assert_eq!(strip.dimensions(), (50, 8), "one row of pixels, drawn 8 high");
    let mut seen = std::collections::BTreeSet::new();
    for column in [0u32, 10, 25, 26, 40, 49] {
        let w = -0.2 + 0.5 * (f64::from(column) + 0.5) / 50.0;
        let check = Command::new(env!("CARGO_BIN_EXE_bcifs"))
            .args(["check", file.to_str().unwrap(), "--param", &format!("w={w}"), "--json"])
            .output()
            .unwrap();
        let check: serde_json::Value = serde_json::from_slice(&check.stdout).unwrap();
        let expected = match (check["converges"].as_bool(), check["per_matrix_condition"].as_bool()) {
            (Some(true), _) => [150, 205, 150],
            (Some(false), Some(false)) => [228, 228, 228],
            (Some(false), _) => [215, 60, 60],
            (None, _) => [240, 200, 80],
        };
        assert_eq!(strip.get_pixel(column, 4).0, expected, "ω = {w}: {check}");
        assert_eq!(strip.get_pixel(column, 0), strip.get_pixel(column, 7), "a column is one value");
        seen.insert(expected);
    }
    assert!(seen.contains(&[150, 205, 150]) && seen.len() > 1, "the strip crosses the convergence range's end");
    assert_eq!(server.json("/api/map.png?x=w&y=w").0, 400, "a map needs two different parameters");
    assert_eq!(server.json("/api/map.png?x=w&xr=1:0").0, 400, "an empty range");
    // The smooth map of the corner cutting: Chaikin (a = b = 1/4) has a junction angle of 0,
    // black; a divergent pixel keeps its verdict's colour.
    let server = Server::start("corner_cutting");
    let (status, _, png) = server.get("/api/map.png?x=a&y=b&xr=-1:1&yr=-1:1&kind=smooth&threshold=5&size=40");
    assert_eq!(status, 200);
    let smooth = image::load_from_memory(&png).unwrap().to_rgb8();
    // Pixel (25, 14) has its centre at (0.275, 0.275), by Chaikin; (0, 39) at (−0.975, −0.975),
    // where the eigenvalue 1 − a − b = 2.95 makes it diverge.
    assert_eq!(smooth.get_pixel(25, 14).0, [20, 20, 20], "near Chaikin the curve is smooth");
    let (_, far) = server.json("/api/check?a=-0.975&b=-0.975");
    assert_eq!(far["check"]["converges"], false);
    assert_eq!(smooth.get_pixel(0, 39).0, [228, 228, 228], "a divergent pixel keeps its verdict's colour");
    assert!(smooth.pixels().all(|p| {
        [[20, 20, 20], [255, 255, 255], [150, 205, 150], [215, 60, 60], [228, 228, 228], [240, 200, 80]].contains(&p.0)
    }));
    assert_eq!(server.json("/api/map.png?x=a&y=b&kind=smooth&threshold=-1").0, 400);
}

#[test]
fn a_page_going_away_stops_its_requests() {
    let server = Server::start("doo_sabin_torus");
    let port = server.port;
    let slow = std::thread::spawn(move || {
        exchange(
            port,
            "GET /api/picture.png?depth=9&size=2000x2000&slot=picture-s1&seq=1 HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n",
        )
    });
    std::thread::sleep(std::time::Duration::from_millis(700));
    // The page's beacon (a POST, as navigator.sendBeacon sends it).
    let raw = exchange(
        port,
        "POST /api/bye?session=s1 HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 0\r\nConnection: close\r\n\r\n",
    );
    assert!(raw.starts_with("HTTP/1.1 200") && raw.contains("\"cancelled\":1"), "{raw}");
    let older = slow.join().unwrap();
    assert!(older.starts_with("HTTP/1.1 409"), "{}", &older[..older.len().min(300)]);
    // Another page's session is not touched; other POSTs are refused.
    assert_eq!(server.json("/api/bye?session=nobody").1["cancelled"], 0);
    assert_eq!(server.json("/api/bye").0, 400);
}

/// `GET path` with the raw `Host` header `host` (None: no such header), HTTP/1.1.
fn get_as(port: u16, path: &str, host: Option<&str>) -> String {
    let host = host.map(|h| format!("Host: {h}\r\n")).unwrap_or_default();
    exchange(port, &format!("GET {path} HTTP/1.1\r\n{host}Connection: close\r\n\r\n"))
}

#[test]
fn only_this_machine_s_names_are_served_and_sloppy_queries_are_refused_briefly() {
    let server = Server::start("corner_cutting");
    let port = server.port;
    // DNS rebinding: a page of another site whose name points here gets nothing, not even the page.
    for path in ["/", "/api/export.toml", "/api/dimension"] {
        for host in ["evil.example", "evil.example:80", &format!("evil.example:{port}"), "127.0.0.1.evil.example"] {
            let raw = get_as(port, path, Some(host));
            assert!(raw.starts_with("HTTP/1.1 403") && raw.contains("is not served"), "{host}{path}: {raw}");
            assert!(!raw.contains("[[arrow]]") && !raw.to_lowercase().contains("access-control-allow-origin"));
        }
    }
    for host in [format!("127.0.0.1:{port}"), format!("localhost:{port}"), "LOCALHOST".into(), format!("[::1]:{port}")]
    {
        assert!(get_as(port, "/api/design", Some(&host)).starts_with("HTTP/1.1 200"), "{host}");
    }
    // HEAD answers as GET without a body; the tab's icon is there.
    let head = exchange(port, "HEAD / HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
    assert!(head.starts_with("HTTP/1.1 200") && !head.contains("<html"), "{head}");
    let (status, headers, icon) = server.get("/favicon.ico");
    assert_eq!(status, 200);
    assert!(headers.contains("image/svg+xml") && String::from_utf8_lossy(&icon).starts_with("<svg"));
    // A parameter given twice is refused; a long value is not echoed back whole.
    let (status, body) = server.json("/api/check?a=0.2&a=0.3");
    assert_eq!(status, 400);
    assert!(body["error"].as_str().unwrap().contains("given twice"), "{body}");
    let long = "9".repeat(100_000) + "x";
    let (status, _, body) = server.get(&format!("/api/check?a={long}"));
    assert_eq!(status, 400);
    assert!(body.len() < 300, "{} bytes: {}", body.len(), String::from_utf8_lossy(&body[..200]));
    assert!(String::from_utf8_lossy(&body).contains("(100001 bytes)"));
    // Ranges whose width overflows are refused at once (their axes never ended).
    let (status, body) = server.json("/api/map.png?x=a&y=b&xr=-1e308:1e308");
    assert_eq!(status, 400, "{body}");
}

#[test]
fn huge_parameters_are_answered_not_spun_on() {
    // nalgebra's SVD of matrices near f64::MAX never converged: the check stayed busy for ever.
    let server = Server::start("corner_cutting");
    let port = server.port;
    let answers: Vec<_> = ["/api/check?a=1e308&b=-1e308", "/api/check?a=1e308", "/api/check?a=-1e300&b=1e300"]
        .into_iter()
        .map(|path| {
            std::thread::spawn(move || {
                let mut stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
                stream.set_read_timeout(Some(std::time::Duration::from_secs(30))).unwrap();
                write!(stream, "GET {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n").unwrap();
                let mut raw = Vec::new();
                stream.read_to_end(&mut raw).map(|_| String::from_utf8_lossy(&raw).to_string())
            })
        })
        .collect();
    for a in answers {
        let raw = a.join().unwrap().expect("answered within 30 s");
        assert!(raw.starts_with("HTTP/1.1 200"), "{}", &raw[..raw.len().min(300)]);
        assert!(raw.contains("\"converges\":false") || raw.contains("\"converges\":null"), "no proof of convergence");
    }
    let out = Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["analyze", "curve", "corner_cutting", "--param", "a=1e308"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let out = Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["analyze", "map", "corner_cutting", "--x", "a=-1e308:1e308", "--y", "b=-1:1", "-o"])
        .arg(std::env::temp_dir().join("bcifs-never-written.png"))
        .output()
        .unwrap();
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("TO - FROM finite"));
}

#[test]
fn a_surface_s_dimension_keeps_to_its_budget_and_its_slot() {
    // The torus at its defaults took 37 s and 3.6 GB; a page asks it after every check.
    let server = Server::start("doo_sabin_torus");
    let port = server.port;
    let started = std::time::Instant::now();
    let (status, dimension) = server.json("/api/dimension");
    assert_eq!(status, 200, "{dimension}");
    assert!(started.elapsed() < std::time::Duration::from_secs(20), "within the time budget");
    // The finest resolution within 768 MiB: fewer scales than the 1 GiB-plus CLI's, a surface's 2 all the same.
    let d = dimension["box_dimension"].as_f64().unwrap();
    assert!((d - 2.0).abs() < 0.2, "{dimension}");
    assert!(dimension["fit"]["scales"].as_array().unwrap().len() >= 4);
    // A newer dimension of the same slot cancels the older: 409, and the newer is answered.
    let older =
        std::thread::spawn(move || get_as(port, "/api/dimension?alpha=0.55&slot=dimension-p&seq=1", Some("127.0.0.1")));
    std::thread::sleep(std::time::Duration::from_millis(300));
    let (status, newer) = server.json("/api/dimension?alpha=0.58&slot=dimension-p&seq=2");
    assert_eq!(status, 200, "{newer}");
    let older = older.join().unwrap();
    assert!(older.starts_with("HTTP/1.1 409"), "{}", &older[..older.len().min(300)]);
    // Maps that need a curve are refused for a surface with their reason, at once.
    let started = std::time::Instant::now();
    let (status, body) = server.json("/api/map.png?x=alpha&y=beta&kind=region&size=16");
    assert_eq!(status, 422, "{body}");
    assert!(started.elapsed() < std::time::Duration::from_secs(5));
}

#[test]
fn a_polygon_mesh_is_explored_with_its_scheme_or_refused_with_what_to_do() {
    let out = Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["explore", "tests/data/cube.off", "--no-open", "--port", "0"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(stderr.contains("is a polygon mesh") && stderr.contains("--scheme"), "{stderr}");
    assert!(!stderr.contains("TOML") && !stderr.contains("3:3"), "{stderr}");
    let mut child = Command::new(env!("CARGO_BIN_EXE_bcifs"))
        .args(["explore", "tests/data/cube.off", "--scheme", "catmull-clark", "--port", "0", "--no-open"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.as_mut().unwrap()).read_line(&mut line).unwrap();
    let port: u16 = line.trim().trim_start_matches("http://127.0.0.1:").trim_end_matches('/').parse().unwrap();
    let design = get_as(port, "/api/design", Some("127.0.0.1"));
    let picture = get_as(port, "/api/picture.png?depth=3&size=64x64", Some("127.0.0.1"));
    let _ = Command::new("kill").args(["-INT", &child.id().to_string()]).status();
    let _ = child.wait();
    assert!(design.starts_with("HTTP/1.1 200") && design.contains("catmull-clark on a mesh of 8 vertices"), "{design}");
    assert!(picture.starts_with("HTTP/1.1 200"), "{}", &picture[..picture.len().min(300)]);
}
