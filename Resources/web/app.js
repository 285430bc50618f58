// ARMadillo's live page: shows what the instrument sends as server-sent events (GET /events) and
// sends the page's two state changes, stage commands (POST /api/stage) and scene parameters
// (POST /api/param), with the session's token in a header. No inline script (the server's
// Content-Security-Policy forbids it); every state is written out in words.
'use strict';

(function () {
  const token = document.querySelector('meta[name="armadillo-token"]').content;
  const $ = (id) => document.getElementById(id);
  const deg = (v) => (v < 0 ? '\u2212' + Math.abs(v).toFixed(1) : v.toFixed(1)) + '\u00b0';
  let last = null;            // the previous status, for announcements
  let sceneShown = null;      // the scene whose parameters are on the page
  let streamUp = false;

  function announce(text) {
    const log = $('announce');
    const p = document.createElement('p');
    p.textContent = text;
    log.appendChild(p);
    while (log.childElementCount > 10) log.removeChild(log.firstElementChild);
  }

  async function post(path, body) {
    const response = await fetch(path, {
      method: 'POST',
      headers: { 'X-Armadillo-Token': token, 'Content-Type': 'text/plain' },
      body: body,
      credentials: 'same-origin',
      cache: 'no-store',
    });
    const text = await response.text();
    if (!response.ok) throw new Error(text.trim() || ('HTTP ' + response.status));
    return JSON.parse(text);
  }

  function showStatus(s) {
    $('orientation').textContent = s.pose
      ? 'Orientation: elevation ' + deg(s.pose.elevation_deg) + ', azimuth ' + deg(s.pose.azimuth_deg) + ', roll ' + deg(s.pose.roll_deg)
      : 'Orientation: no pose yet.';
    $('source').textContent = s.source;
    $('connected').textContent = s.connected ? 'connected: data arrives' : 'not connected: no data from the source';
    $('rate').textContent = s.rate_hz.toFixed(0) + ' packets per second (' + s.packets + ' in all)';
    $('drops').textContent = s.bad_packets + ' bad packets, ' + s.gaps + ' gaps, ' + s.dropped + ' samples dropped';
    $('sender').textContent = s.sender || 'none detected';
    $('time').textContent = s.t.toFixed(1) + ' s';
    $('stage-state').textContent = s.panicked
      ? 'Stage: PANIC \u2014 every motor is off until Resume (' + s.panics + ' panic' + (s.panics === 1 ? '' : 's') + ').'
      : 'Stage: playing' + (s.panics > 0 ? ' (' + s.panics + ' panic' + (s.panics === 1 ? '' : 's') + ' so far).' : '.');
    $('scene').textContent = 'Scene: ' + s.scene + (s.cue >= 0 ? ', cue ' + (s.cue + 1) + ' of ' + s.cue_count : '') + '.';
    if (s.cue >= 0 && $('cue').options.length > 0 && document.activeElement !== $('cue')) $('cue').value = String(s.cue);
    showMessages(s.messages);
    showWalk(s.walk);
    showCalibration(s.calibration);
    showTouch(s.touch);
  }

  function showTouch(t) {
    let state;
    if (!t.available) state = 'Not available: ' + t.why + '.';
    else if (t.asking) state = 'Stimulus ' + t.stimuli + (t.comfort ? ' (comfortable level)' : '') + ' played: answer it.';
    else if (t.running) state = 'Stimulus ' + t.stimuli + (t.comfort ? ' (comfortable level)' : '') + ': feel\u2026';
    else if (t.finished) state = 'Complete: ' + t.result + '.';
    else state = 'Not running.';
    $('touch-state').textContent = state;
    $('touch-question').textContent = t.asking ? 'Question: ' + t.question : '';
    $('touch-note').textContent = t.note ? 'Last: ' + t.note : '';
    $('touch-begin').disabled = !t.available || t.running;
    for (const id of ['touch-felt', 'touch-not-felt', 'touch-again']) $(id).disabled = !t.asking;
    $('touch-cancel').disabled = !t.running;
    $('touch-download').hidden = !t.finished;
  }

  function showCalibration(c) {
    let state;
    if (!c.available) state = 'Not available: ' + c.why + '.';
    else if (c.finished) state = c.title + '.';
    else if (c.running) state = c.title + ' — ' + Math.round(100 * c.progress) + '% of its data' + (c.ready ? ', ready: take it with Next step.' : '.');
    else state = 'Not running.';
    $('cal-state').textContent = state;
    $('cal-instruction').textContent = c.running ? 'What to do: ' + c.instruction : '';
    $('cal-note').textContent = c.note ? 'Last: ' + c.note : '';
    $('cal-begin').disabled = !c.available;
    for (const id of ['cal-next', 'cal-skip', 'cal-cancel']) $(id).disabled = !c.running;
    $('cal-download').hidden = !c.finished;
  }

  function showMessages(list) {
    const ol = $('messages');
    $('messages-none').hidden = list.length > 0;
    ol.textContent = '';
    ol.hidden = list.length === 0;
    for (const m of list) {
      const li = document.createElement('li');
      li.textContent = m;
      ol.appendChild(li);
    }
  }

  function showWalk(w) {
    $('walk-section').hidden = !w;
    if (!w) return;
    if (w.finished) {
      $('walk').textContent = 'Route ' + w.route + ' finished: ' + w.arrivals + ' waypoints reached.';
      return;
    }
    const name = w.name ? ' (' + w.name + ')' : '';
    const distance = w.distance_m === null ? 'distance not known yet' : w.distance_m.toFixed(0) + ' m away';
    const bearing = w.bearing_deg === null ? 'bearing not known yet' : 'bearing ' + w.bearing_deg.toFixed(0) + '\u00b0 from north';
    $('walk').textContent = 'Route ' + w.route + ': next waypoint ' + w.waypoint + ' of ' + w.waypoints + name + ', ' +
      distance + ', ' + bearing + '. Position: ' + w.fix + '.';
  }

  function announceChanges(s) {
    if (!last) {
      announce(s.connected ? 'Connected to ' + s.source + '.' : 'Waiting for data from ' + s.source + '.');
    } else {
      if (s.connected && !last.connected) announce('Connected: data from ' + s.source + ' again.');
      if (!s.connected && last.connected) announce('Lost: no data from ' + s.source + '.');
      if (s.panics > last.panics) announce('Panic: every motor is off.');
      if (!s.panicked && last.panicked) announce('Resumed.');
      if (s.cue !== last.cue && s.cue >= 0) announce('Cue ' + (s.cue + 1) + ': ' + s.scene + '.');
      if (s.messages.length > 0 && s.messages[0] !== last.messages[0]) announce('Message: ' + s.messages[0]);
      if (s.calibration.running && (s.calibration.step !== last.calibration.step || !last.calibration.running))
        announce('Calibration ' + s.calibration.title + ': ' + s.calibration.instruction);
      if (s.calibration.ready && !last.calibration.ready) announce('Calibration: this step has enough data.');
      if (s.calibration.finished && !last.calibration.finished) announce('Calibration complete.');
      if (s.touch.asking && (!last.touch.asking || s.touch.stimuli !== last.touch.stimuli)) announce(s.touch.question);
      if (s.touch.finished && !last.touch.finished) announce('Sensitivity test complete: ' + s.touch.result + '.');
      if (s.walk && last.walk && s.walk.arrivals > last.walk.arrivals)
        announce(s.walk.finished ? 'Arrived: the route is finished.' : 'Arrived at a waypoint; next is ' + s.walk.waypoint + '.');
    }
  }

  function paramControl(p, i) {
    const row = document.createElement('div');
    row.className = 'param';
    const label = document.createElement('label');
    label.htmlFor = 'param-' + i;
    label.textContent = p.name + (p.unit ? ' (' + p.unit + ')' : '') + (p.choices.length ? '' : ', ' + p.min + ' to ' + p.max);
    let input;
    if (p.choices.length) {
      input = document.createElement('select');
      p.choices.forEach((c, k) => input.add(new Option(c, String(k))));
      input.value = String(Math.round(p.value));
    } else {
      input = document.createElement('input');
      input.type = 'number';
      input.min = p.min;
      input.max = p.max;
      input.step = 'any';
      input.value = p.value;
    }
    input.id = 'param-' + i;
    input.dataset.id = p.id;
    input.dataset.sent = input.value;
    row.append(label, input);
    return row;
  }

  async function loadScene() {
    const response = await fetch('api/scene', { credentials: 'same-origin', cache: 'no-store' });
    const scene = await response.json();
    sceneShown = scene.scene;
    $('params-legend').textContent = 'Parameters of the scene ' + scene.scene;
    const box = $('params');
    box.textContent = '';
    scene.parameters.forEach((p, i) => box.appendChild(paramControl(p, i)));
    $('params-apply').hidden = scene.parameters.length === 0;
    if (scene.parameters.length === 0) box.textContent = 'This scene has no parameters of its own.';
    const choice = $('scene-choice');
    choice.textContent = '';
    scene.scenes.forEach((name) => choice.add(new Option(name, name, false, name === scene.scene)));
    $('scene-form').hidden = scene.scenes.length === 0;
    if (scene.scene_choice) $('scene-result').textContent = 'The scene cannot be changed here: ' + scene.scene_choice + '.';
    const cue = $('cue');
    cue.textContent = '';
    scene.cues.forEach((name, i) => cue.add(new Option((i + 1) + ': ' + name, String(i))));
    $('cue-form').hidden = scene.cues.length === 0;
  }

  async function applyParameters(event) {
    event.preventDefault();
    const said = [];
    for (const input of $('params').querySelectorAll('input, select')) {
      if (input.value === input.dataset.sent) continue;
      try {
        const r = await post('api/param', 'id=' + input.dataset.id + '&value=' + Number(input.value));
        input.value = String(input.tagName === 'SELECT' ? Math.round(r.value) : r.value);
        input.dataset.sent = input.value;
        said.push(r.id + ' set to ' + r.value);
      } catch (e) {
        said.push(input.dataset.id + ' not set: ' + e.message);
      }
    }
    $('params-result').textContent = said.length ? said.join('; ') + '.' : 'Nothing changed.';
  }

  async function stageCommand(body, what) {
    try {
      const r = await post('api/stage', body);
      $('stage-result').textContent = what + ' sent at session time ' + r.t.toFixed(3) + ' s.';
    } catch (e) {
      $('stage-result').textContent = what + ' was not taken: ' + e.message;
      announce(what + ' was not taken.');
    }
  }

  function connect() {
    const events = new EventSource('events');
    events.onmessage = (e) => {
      const s = JSON.parse(e.data);
      if (!streamUp) $('connection').textContent = 'Live: this page shows the instrument as it plays.';
      streamUp = true;
      announceChanges(s);
      showStatus(s);
      if (s.scene !== sceneShown) loadScene().catch(() => {});
      last = s;
    };
    events.onerror = () => {
      if (streamUp) announce('Lost the connection to the instrument; trying again.');
      streamUp = false;
      $('connection').textContent = 'Not connected to the instrument (it may have ended); trying again.';
    };
  }

  for (const b of document.querySelectorAll('button[data-cal]'))
    b.addEventListener('click', async () => {
      try {
        showCalibration((await post('api/calibration', b.dataset.cal)).calibration);
      } catch (e) {
        $('cal-note').textContent = b.textContent + ' was not taken: ' + e.message;
      }
    });
  for (const b of document.querySelectorAll('button[data-touch]'))
    b.addEventListener('click', async () => {
      try {
        showTouch((await post('api/touch', b.dataset.touch)).touch);
      } catch (e) {
        $('touch-note').textContent = b.textContent + ' was not taken: ' + e.message;
      }
    });
  for (const b of document.querySelectorAll('button[data-command]'))
    b.addEventListener('click', () => stageCommand(b.dataset.command, b.textContent));
  $('params-form').addEventListener('submit', applyParameters);
  $('scene-form').addEventListener('submit', async (e) => {
    e.preventDefault();
    const name = $('scene-choice').value;
    try {
      await post('api/scene', 'scene=' + name);
      $('scene-result').textContent = 'Scene ' + name + ' asked for: it plays from the next control step.';
    } catch (err) {
      $('scene-result').textContent = err.message;
    }
  });
  $('cue-form').addEventListener('submit', (e) => {
    e.preventDefault();
    stageCommand('cue=' + $('cue').value, 'Cue ' + (Number($('cue').value) + 1));
  });
  connect();
})();
