// Class 1 exclusive owner with npm st-ethernet-ip's IO.Scanner on the generic profile
// (input 100, output 150, config 151; sizes are data bytes only, RPI whole ms >= 8).
// Reads {"host", "rpi_ms", "seconds"} as JSON from stdin; writes a pattern in O->T, watches
// T->O for it, then Forward_Close. Prints one JSON line:
// {"connected", "echoed", "forward_close"} (forward_close: true if it was answered).
const { IO } = require("st-ethernet-ip");

let input = "";
process.stdin.on("data", (d) => { input += d; });
process.stdin.on("end", () => {
  const req = JSON.parse(input);
  const result = { connected: false, echoed: false, forward_close: false };
  const scanner = new IO.Scanner(2222, "0.0.0.0");
  const conn = scanner.addConnection(
    {
      configInstance: { assembly: 151, size: 10 },
      inputInstance: { assembly: 100, size: 32 },
      outputInstance: { assembly: 150, size: 32 },
    },
    req.rpi_ms,
    req.host,
  );
  const pattern = Buffer.from(Array.from({ length: 32 }, (_, i) => (i * 11 + 5) & 0xff));
  conn.outputData = Buffer.from(pattern);
  conn.on("connected", () => { result.connected = true; });
  const poll = setInterval(() => {
    if (Buffer.compare(conn.inputData, pattern) === 0) result.echoed = true;
  }, 20);
  setTimeout(async () => {
    clearInterval(poll);
    conn.run = false;
    try {
      await conn.tcpController.forwardClose();
      result.forward_close = true;
    } catch (e) {
      result.forward_close = false;
    }
    console.log(JSON.stringify(result));
    process.exit(0);
  }, req.seconds * 1000);
});
