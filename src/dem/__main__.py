from dem.cli import console

console()
