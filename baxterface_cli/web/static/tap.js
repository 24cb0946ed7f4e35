// Where a tap landed on a face drawn letterboxed (object-fit: contain) in an element, as fractions
// of the frame: what POST /api/touch takes. Shared by the studio's preview and the screen's page;
// the server finds what is drawn there.
"use strict";
window.baxterfaceTapAt = function (element, frameWidth, frameHeight, event) {
  const box = element.getBoundingClientRect();
  const scale = Math.min(box.width / frameWidth, box.height / frameHeight);
  const left = box.left + (box.width - frameWidth * scale) / 2;
  const top = box.top + (box.height - frameHeight * scale) / 2;
  return {
    x: (event.clientX - left) / (frameWidth * scale),
    y: (event.clientY - top) / (frameHeight * scale),
  };
};
