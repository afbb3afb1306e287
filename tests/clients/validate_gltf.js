// Validates glTF files with the Khronos glTF validator (npm gltf-validator),
// one JSON line per file: {"file", "errors", "warnings", "messages"} (the
// messages of severity error or warning). Used by the Rust tests.
const validator = require('gltf-validator');
const fs = require('fs');

(async () => {
    for (const file of process.argv.slice(2)) {
        const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), { maxIssues: 0 });
        const messages = report.issues.messages
            .filter((m) => m.severity <= 1)
            .slice(0, 20)
            .map((m) => `${m.code}: ${m.message} (${m.pointer || ''})`);
        console.log(JSON.stringify({ file, errors: report.issues.numErrors, warnings: report.issues.numWarnings, messages }));
    }
})().catch((e) => { console.error(e); process.exit(1); });
