"""The screen: the face alone, for any screen with a browser, served through the studio's web API."""
