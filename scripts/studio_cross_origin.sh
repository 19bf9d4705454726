#!/usr/bin/env bash
# Can a page of another origin get `gridshell studio` to do any work? (docs/studio.md, "What the
# studio protects".) Starts a studio on a free port of 127.0.0.1, and a second local server
# (python3 -m http.server) on another port serving an attacking page; headless Chromium opens
# that page, which tries every studio route by fetch (with and without a guessed token, cors and
# no-cors), XMLHttpRequest, <img>, <script>, a <form> POST of an upload into an iframe, and an
# <iframe> of the studio's page. Passes (exit 0) when the studio's log shows no /api request
# answered other than 403/405 and no design stage, and the page read nothing from the studio.
# Traffic: 127.0.0.1 only; every wait is bounded.
#
#   bash scripts/studio_cross_origin.sh [build/gridshell]
set -euo pipefail
exe=$(realpath "${1:-build/gridshell}")
chromium=$(command -v chromium || command -v chromium-browser || true)
[ -n "$chromium" ] || { echo "no chromium" >&2; exit 77; }
work=$(mktemp -d)
studio_pid=""
web_pid=""
cleanup() {
  [ -n "$studio_pid" ] && kill "$studio_pid" 2>/dev/null || true
  [ -n "$web_pid" ] && kill "$web_pid" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

"$exe" studio builtin:dome:res=8 --port 0 >"$work/studio.log" 2>&1 </dev/null &
studio_pid=$!
port=""
for _ in $(seq 1 600); do
  port=$(sed -n 's|^studio: http://127\.0\.0\.1:\([0-9]*\)/$|\1|p' "$work/studio.log" | head -1)
  [ -n "$port" ] && break
  sleep 0.1
done
[ -n "$port" ] || { echo "the studio did not start" >&2; cat "$work/studio.log" >&2; exit 1; }

other=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
studio="http://127.0.0.1:$port"
mkdir -p "$work/site"
cat >"$work/site/attack.html" <<HTML
<!doctype html><html><body>
<pre id="log"></pre>
<iframe name="sink" style="display:none"></iframe>
<iframe id="framed" src="$studio/"></iframe>
<script>
const studio = '$studio';
const log = (s) => { document.getElementById('log').textContent += s + '\n'; };
const routes = ['/', '/api/surfaces', '/api/design?cells=120&analyze=nonlinear',
  '/api/config.json?cells=100', '/api/export.zip?cells=100',
  '/api/design?surface=builtin:barrel:length=85899346'];
async function attempt(name, f) {
  try { log(name + ': ' + await f()); } catch (e) { log(name + ': error ' + e.name); }
}
async function main() {
  for (const r of routes) {
    await attempt('cors ' + r, async () => {
      const x = await fetch(studio + r);
      return 'READ ' + x.status + ' ' + (await x.text()).slice(0, 40);
    });
    await attempt('token ' + r, async () => {
      const x = await fetch(studio + r, { headers: { 'X-Gridshell-Token': '00000000000000000000000000000000' } });
      return 'READ ' + x.status;
    });
    await attempt('no-cors ' + r, async () => {
      const x = await fetch(studio + r, { mode: 'no-cors' });
      return x.type === 'opaque' ? 'opaque' : 'READ ' + x.status;
    });
    await attempt('xhr ' + r, () => new Promise((ok, no) => {
      const q = new XMLHttpRequest();
      q.open('GET', studio + r);
      q.onload = () => ok('READ ' + q.status);
      q.onerror = () => no(new Error('xhr'));
      q.send();
    }));
    const img = new Image();
    img.src = studio + r + (r.includes('?') ? '&' : '?') + 'img=1';
    const s = document.createElement('script');
    s.src = studio + r;
    document.body.appendChild(s);
  }
  await attempt('post upload', async () => {
    const x = await fetch(studio + '/api/surface?name=a.off', { method: 'POST', mode: 'no-cors',
      body: 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' });
    return x.type === 'opaque' ? 'opaque' : 'READ ' + x.status;
  });
  const form = document.createElement('form');
  form.method = 'POST';
  form.action = studio + '/api/surface?name=b.off';
  form.enctype = 'text/plain';
  form.target = 'sink';
  const field = document.createElement('input');
  field.name = 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n#';
  field.value = '';
  form.appendChild(field);
  document.body.appendChild(form);
  form.submit();
  await attempt('read frame', async () => {
    const d = document.getElementById('framed').contentDocument;
    return d ? 'READ ' + d.documentElement.outerHTML.length : 'blocked';
  });
  await new Promise((r) => setTimeout(r, 3000));
  document.body.setAttribute('data-done', '1');
}
main();
</script></body></html>
HTML
(cd "$work/site" && exec python3 -m http.server "$other" --bind 127.0.0.1) >"$work/web.log" 2>&1 &
web_pid=$!
for _ in $(seq 1 100); do
  python3 -c "import socket; socket.create_connection(('127.0.0.1', $other), 1)" 2>/dev/null && break
  sleep 0.1
done

timeout 120 "$chromium" --headless --no-sandbox --disable-gpu --user-data-dir="$work/profile" \
  --host-resolver-rules="MAP * ~NOTFOUND, EXCLUDE 127.0.0.1" --virtual-time-budget=15000 \
  --dump-dom "http://127.0.0.1:$other/attack.html" >"$work/dom.html" 2>"$work/chromium.log" || true
sleep 1

token=$(timeout 10 python3 - "$port" <<'PY'
import http.client, re, sys
c = http.client.HTTPConnection("127.0.0.1", int(sys.argv[1]), timeout=5)
c.request("GET", "/")
m = re.search(r'name="gridshell-token" content="([0-9a-f]+)"', c.getresponse().read().decode())
print(m.group(1) if m else "")
PY
)
echo "--- what the attacking page saw"
sed -n '/<pre id="log">/,/<\/pre>/p' "$work/dom.html" | sed 's/<[^>]*>//g' >"$work/seen.txt"
cat "$work/seen.txt"
echo "--- what the studio answered"
{ grep -E 'studio: [A-Z]+ /' "$work/studio.log" || true; } | sed 's/^.*studio: /studio: /' | sort | uniq -c
fail=0
grep -q 'data-done="1"' "$work/dom.html" || { echo "FAIL: the attacking page did not finish"; fail=1; }
grep -q 'READ' "$work/seen.txt" && { echo "FAIL: the page read an answer of the studio"; fail=1; }
[ -n "$token" ] && grep -q "$token" "$work/dom.html" && { echo "FAIL: the token leaked"; fail=1; }
attempts=$(grep -cE 'studio: (GET|POST|OPTIONS|[A-Z]+) /' "$work/studio.log" || true)
[ "$attempts" -gt 0 ] || { echo "FAIL: no request reached the studio (nothing was tried)"; fail=1; }
if grep -E 'studio: [A-Z]+ /api/[^ ]* → ' "$work/studio.log" | grep -vqE '→ (403|405)'; then
  echo "FAIL: an /api request from the other origin was answered"; fail=1
fi
if grep -qE '^\[(stress|field|metric|tessellation|regularization|analysis|objective)' "$work/studio.log"; then
  echo "FAIL: the studio designed something"; fail=1
fi
if [ "$fail" = 0 ]; then
  echo "PASS: $attempts requests from http://127.0.0.1:$other reached the studio; none did any work"
fi
exit "$fail"
